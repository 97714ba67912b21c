// Calls a generic lambda with the decoder type of the image's layout, so traversal code is
// compiled once per layout with the decode inlined.
#pragma once
#include <string>

#include "layout/cluster_layout.h"
#include "layout/dfl_layout.h"
#include "layout/odfl_layout.h"
#include "layout/profile_layout.h"
#include "layout/subtree_layout.h"
#include "layout/veb_layout.h"
#include "layout/memory_image.h"
#include "util/error.h"

namespace rtusim {

template <class F>
decltype(auto) with_layout_decoder(const MemoryImage& image, F&& f) {
  if (image.layout == "dfl") return f.template operator()<DflLayout>();
  if (image.layout == "odfl") return f.template operator()<OdflLayout>();
  if (image.layout == "subtree") return f.template operator()<SubtreeLayout>();
  if (image.layout == "subtree-bfs") return f.template operator()<SubtreeLayout>();
  if (image.layout == "veb") return f.template operator()<VebLayout>();
  if (image.layout == "cluster") return f.template operator()<ClusterLayout>();
  if (image.layout == "profile") return f.template operator()<ProfileLayout>();
  throw std::logic_error("no decoder for layout '" + image.layout + "'");
}

}  // namespace rtusim
