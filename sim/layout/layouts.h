// The registry of layouts (layout.kind): one entry per layout, in the order `rtusim keys` and
// errors list them. A new layout is its own file (a final Layout with kName, build_image() and a
// static decode() for traversal) plus its entry here; make_layout() and with_layout_decoder()
// both walk this list.
#pragma once
#include "layout/dfl_layout.h"
#include "layout/odfl_layout.h"
#include "layout/subtree_layout.h"
#include "util/type_registry.h"

namespace rtusim {

using Layouts = TypeRegistry<DflLayout, OdflLayout, SubtreeLayout>;

}  // namespace rtusim
