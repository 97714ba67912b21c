// The functional tier on a chip of several units or with an L2 (chip.*, l2.*): each ray is
// dealt to a unit (chip/ray_dealer.h) and traversed through that unit's private caches; the
// units' requests reach the shared L2 in the chip's turn order (chip/chip_caches.h). Hits are
// the plain functional tier's; each pixel is charged the DRAM bytes its rays caused.
#pragma once
#include <span>

#include "chip/chip_caches.h"
#include "chip/ray_dealer.h"
#include "layout/memory_image.h"
#include "tracer/trace_backend.h"

namespace rtusim {

class ChipFunctionalBackend final : public TraceBackend {
 public:
  // `width`, `pixels`: the frame's (tiles and pixel charges).
  ChipFunctionalBackend(const MemoryImage& image, const FetchCacheParams& caches,
                        const ChipParams& chip, uint32_t width, uint32_t pixels);
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override;
  // Parallel tracing: every fetch is logged (the default ReplayNeeds), as each unit's caches
  // see only their own rays' fetches.
  const MemoryImage* replay_image() const override { return &image_; }
  void replay(const FetchLog& log) override;

  // The frame is over: the L2 takes the requests still waiting.
  void end_frame() { chip_.drain_all(); }
  const ChipCaches& chip() const { return chip_; }
  ChipCaches& chip() { return chip_; }

 private:
  const MemoryImage& image_;
  ChipCaches chip_;
  RayDealer dealer_;
};

}  // namespace rtusim
