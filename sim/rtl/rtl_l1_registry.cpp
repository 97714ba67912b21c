#include "rtl/rtl_l1_registry.h"

#include "util/error.h"

namespace rtusim {

namespace {

// An empty table still needs one element; kCount says how many are real.
constexpr RtlL1Build kBuilds[] = {
#include "rtl_l1_builds.inc"
    {0, 0, 0, "", ""},
};
constexpr std::size_t kCount = std::size(kBuilds) - 1;

}  // namespace

std::span<const RtlL1Build> rtl_l1_builds() { return {kBuilds, kCount}; }

std::string rtl_l1_builds_text() {
  std::string text;
  for (const RtlL1Build& b : rtl_l1_builds()) {
    if (!text.empty()) text += ", ";
    text += std::to_string(b.size_bytes) + "/" + std::to_string(b.assoc) + "/" +
            std::to_string(b.line_bytes) + "/" + std::string(b.policy);
  }
  return text.empty() ? "none" : text;
}

const RtlL1Build* find_rtl_l1_build(const CacheParams& p) {
  for (const RtlL1Build& b : rtl_l1_builds())
    if (b.size_bytes == p.size_bytes && b.assoc == p.assoc && b.line_bytes == p.line_bytes &&
        b.policy == p.policy)
      return &b;
  return nullptr;
}

const RtlL1Build& rtl_l1_build(const CacheParams& p) {
  if (const RtlL1Build* b = find_rtl_l1_build(p)) return *b;
  throw InputError("l1.model = rtl: no RTL build for l1.size=" + std::to_string(p.size_bytes) +
                   ", l1.assoc=" + std::to_string(p.assoc) + ", l1.line=" +
                   std::to_string(p.line_bytes) + ", l1.policy=" + p.policy +
                   " (built: " + rtl_l1_builds_text() + ", as size/assoc/line/policy)");
}

}  // namespace rtusim
