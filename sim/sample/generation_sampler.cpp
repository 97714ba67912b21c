#include "sample/generation_sampler.h"

#include <algorithm>
#include <stdexcept>

#include "sample/sampled_frame.h"
#include "util/stats.h"

namespace rtusim {

GenerationSampler::GenerationSampler(TraceBackend& plain, TierRun& tier,
                                     std::vector<int32_t> unit_of_pixel, int units, int warm_rays)
    : plain_(plain), tier_(tier), unit_of_pixel_(std::move(unit_of_pixel)),
      warm_rays_(std::max(0, warm_rays)), values_(units), rays_(units, 0.0) {}

void GenerationSampler::send(std::span<const RayRecord> rays, std::span<const Hit> expected) {
  scratch_.assign(rays.size(), Hit{});
  tier_.backend().trace(rays, scratch_);
  for (size_t i = 0; i < rays.size(); ++i)
    if (scratch_[i].triangle != expected[i].triangle || scratch_[i].t != expected[i].t)
      throw std::logic_error("sampled wavefront: the tier's hit differs from plain traversal's");
}

void GenerationSampler::warm(std::span<const RayRecord> batch, std::span<const Hit> hits,
                             size_t first) {
  const uint64_t at = batch_start_ + first;
  const uint64_t from = std::max(at - std::min<uint64_t>(at, warm_rays_), next_unsent_);
  if (from >= at) return;
  // The span may begin in earlier batches (kept in tail_) and end in this one.
  std::vector<RayRecord> rays;
  std::vector<Hit> expected;
  for (uint64_t g = from; g < at; ++g) {
    if (g < batch_start_) {
      const size_t back = batch_start_ - g;
      rays.push_back(tail_[tail_.size() - back]);
      expected.push_back(tail_hits_[tail_hits_.size() - back]);
    } else {
      rays.push_back(batch[g - batch_start_]);
      expected.push_back(hits[g - batch_start_]);
    }
  }
  send(rays, expected);
  rays_warmed_ += rays.size();
}

void GenerationSampler::trace(std::span<const RayRecord> rays, std::span<Hit> hits) {
  plain_.trace(rays, hits);
  Stats before, after;
  size_t i = 0;
  while (i < rays.size()) {
    const int32_t unit = unit_of_pixel_.at(rays[i].pixel);
    if (unit < 0) {
      ++i;
      continue;
    }
    // The run: this unit's consecutive rays of the batch, warmed, then measured.
    size_t end = i + 1;
    while (end < rays.size() && unit_of_pixel_[rays[end].pixel] == unit) ++end;
    warm(rays, hits, i);
    tier_.write_stats(before);
    send(rays.subspan(i, end - i), hits.subspan(i, end - i));
    tier_.write_stats(after);
    next_unsent_ = batch_start_ + end;
    SampledFrame::add_extensive_change(before, after, values_[unit]);
    rays_[unit] += double(end - i);
    rays_measured_ += end - i;
    i = end;
  }
  // The sequence's last warm_rays_ rays, for warming runs early in the next batch.
  tail_.insert(tail_.end(), rays.begin(), rays.end());
  tail_hits_.insert(tail_hits_.end(), hits.begin(), hits.end());
  if (tail_.size() > size_t(warm_rays_)) {
    const size_t drop = tail_.size() - warm_rays_;
    tail_.erase(tail_.begin(), tail_.begin() + drop);
    tail_hits_.erase(tail_hits_.begin(), tail_hits_.begin() + drop);
  }
  batch_start_ += rays.size();
}

}  // namespace rtusim
