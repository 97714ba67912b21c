// The host side of the unit: holds the ray batch the tracer posted, hands rays to the traversal
// unit in batch order and collects their hits. No process of its own.
#pragma once
#include <cstdint>
#include <span>

#include <systemc>

#include "tracer/trace_backend.h"

namespace rtusim {

class HostInterface : public sc_core::sc_module {
 public:
  explicit HostInterface(const sc_core::sc_module_name& name) : sc_module(name) {}

  // Posts a batch (called between simulation runs): hits[i] receives the hit of rays[i].
  void post(std::span<const RayRecord> rays, std::span<Hit> hits) {
    rays_ = rays;
    hits_ = hits;
    next_ = 0;
    completed_ = 0;
    posted_.notify(sc_core::SC_ZERO_TIME);
  }
  const sc_core::sc_event& posted() const { return posted_; }
  bool has_work() const { return next_ < rays_.size(); }

  // The next ray of the batch, or false when all have been handed out.
  bool next(uint32_t& index) {
    if (next_ >= rays_.size()) return false;
    index = static_cast<uint32_t>(next_++);
    return true;
  }
  const RayRecord& ray(uint32_t index) const { return rays_[index]; }
  void complete(uint32_t index, const Hit& hit) {
    hits_[index] = hit;
    ++completed_;
  }
  bool batch_done() const { return completed_ == rays_.size(); }

 private:
  std::span<const RayRecord> rays_;
  std::span<Hit> hits_;
  size_t next_ = 0, completed_ = 0;
  sc_core::sc_event posted_;
};

}  // namespace rtusim
