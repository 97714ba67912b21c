// A TraceBackend wrapper that shows a progress bar on stderr for runs longer than a few seconds
// (only when stderr is a terminal): the share of primary rays issued.
#pragma once
#include <chrono>
#include <string>

#include "tracer/trace_backend.h"

namespace rtusim {

class ProgressBackend final : public TraceBackend {
 public:
  ProgressBackend(TraceBackend& inner, uint64_t primary_rays, std::string label);
  ~ProgressBackend() override;
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override;
  const MemoryImage* replay_image() const override { return inner_.replay_image(); }
  ReplayNeeds replay_needs() const override { return inner_.replay_needs(); }
  void replay(const FetchLog& log) override;

 private:
  void advance(uint64_t primary_rays);
  void draw(bool final);

  TraceBackend& inner_;
  uint64_t total_, done_ = 0;
  std::string label_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_, last_draw_;
  double quiet_seconds_;  // nothing drawn before this
};

}  // namespace rtusim
