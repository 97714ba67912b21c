// Calls a generic lambda with the decoder type of the image's layout, so traversal code is
// compiled once per layout with the decode inlined.
#pragma once
#include "layout/layouts.h"
#include "layout/memory_image.h"

namespace rtusim {

template <class F>
decltype(auto) with_layout_decoder(const MemoryImage& image, F&& f) {
  return Layouts::dispatch(image.layout, f);
}

}  // namespace rtusim
