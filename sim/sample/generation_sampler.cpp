#include "sample/generation_sampler.h"

#include <algorithm>
#include <stdexcept>

#include <oneapi/tbb/task_group.h>

#include "sample/sampled_frame.h"
#include "util/stats.h"

namespace rtusim {

GenerationSampler::GenerationSampler(TraceBackend& plain, TierRun& tier,
                                     std::vector<int32_t> unit_of_pixel, int units, int warm_rays)
    : plain_(plain), tier_(tier), unit_of_pixel_(std::move(unit_of_pixel)),
      warm_rays_(std::max(0, warm_rays)), values_(units), rays_(units, 0.0) {}

void GenerationSampler::check(std::span<const Hit> tier, std::span<const Hit> plain) {
  for (size_t i = 0; i < tier.size(); ++i)
    if (tier[i].triangle != plain[i].triangle || tier[i].t != plain[i].t)
      throw std::logic_error("sampled wavefront: the tier's hit differs from plain traversal's");
}

std::span<Hit> GenerationSampler::tier_hits_room(size_t n) {
  tier_hits_.resize(tier_hits_.size() + n);
  return std::span<Hit>(tier_hits_).last(n);
}

void GenerationSampler::warm(std::span<const RayRecord> batch, size_t first) {
  const uint64_t at = batch_start_ + first;
  const uint64_t from = std::max(at - std::min<uint64_t>(at, warm_rays_), next_unsent_);
  if (from >= at) return;
  // The span may begin in earlier batches (kept in tail_) and end in this one.
  std::vector<RayRecord> rays;
  for (uint64_t g = from; g < at; ++g)
    rays.push_back(g < batch_start_ ? tail_[tail_.size() - (batch_start_ - g)]
                                    : batch[g - batch_start_]);
  scratch_.assign(rays.size(), Hit{});
  tier_.backend().trace(rays, scratch_);
  const size_t earlier = batch_start_ > from ? size_t(batch_start_ - from) : 0;
  check(std::span<const Hit>(scratch_).first(earlier),
        std::span<const Hit>(tail_hits_).last(earlier));
  if (earlier < rays.size()) {
    const size_t begin = size_t(from + earlier - batch_start_);
    sent_.push_back({begin, first, tier_hits_.size()});
    const std::span<Hit> room = tier_hits_room(first - begin);
    std::copy(scratch_.begin() + earlier, scratch_.end(), room.begin());
  }
  rays_warmed_ += rays.size();
}

void GenerationSampler::trace(std::span<const RayRecord> rays, std::span<Hit> hits) {
  // Plain traversal of the whole batch on the workers, the tier's runs on this thread.
  tbb::task_group plain;
  plain.run([&] { plain_.trace(rays, hits); });
  try {
    tier_hits_.clear();
    sent_.clear();
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
      warm(rays, i);
      tier_.write_stats(before);
      sent_.push_back({i, end, tier_hits_.size()});
      tier_.backend().trace(rays.subspan(i, end - i), tier_hits_room(end - i));
      tier_.write_stats(after);
      next_unsent_ = batch_start_ + end;
      SampledFrame::add_extensive_change(before, after, values_[unit]);
      rays_[unit] += double(end - i);
      rays_measured_ += end - i;
      i = end;
    }
  } catch (...) {
    plain.wait();
    throw;
  }
  plain.wait();
  for (const Sent& s : sent_)
    check(std::span<const Hit>(tier_hits_).subspan(s.hits, s.end - s.begin),
          hits.subspan(s.begin, s.end - s.begin));
  // The sequence's last warm_rays_ rays, for warming runs early in the next batch.
  const size_t keep = std::min(rays.size(), size_t(warm_rays_));
  tail_.insert(tail_.end(), rays.end() - keep, rays.end());
  tail_hits_.insert(tail_hits_.end(), hits.end() - keep, hits.end());
  if (tail_.size() > size_t(warm_rays_)) {
    const size_t drop = tail_.size() - warm_rays_;
    tail_.erase(tail_.begin(), tail_.begin() + drop);
    tail_hits_.erase(tail_hits_.begin(), tail_hits_.begin() + drop);
  }
  batch_start_ += rays.size();
}

}  // namespace rtusim
