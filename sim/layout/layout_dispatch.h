// Calls a generic lambda with the decoder type of the image's layout, so traversal code is
// compiled once per layout with the decode inlined.
#pragma once
#include <string>

#include "layout/dfl_layout.h"
#include "layout/memory_image.h"
#include "util/error.h"

namespace rtusim {

template <class F>
decltype(auto) with_layout_decoder(const MemoryImage& image, F&& f) {
  if (image.layout == "dfl") return f.template operator()<DflLayout>();
  throw std::logic_error("no decoder for layout '" + image.layout + "'");
}

}  // namespace rtusim
