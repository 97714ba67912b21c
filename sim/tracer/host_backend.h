// Traces ray batches on the host with the shared traversal step function, counting fetches
// per stream (no memory model).
#pragma once
#include <array>
#include <memory>

#include "layout/memory_image.h"
#include "tracer/trace_backend.h"

namespace rtusim {

// Fetches and bytes per stream (indexed by Stream).
struct FetchCounts {
  static constexpr bool kFetchOrderFree = true;  // sums: batched rays may report interleaved
  std::array<uint64_t, 3> fetches{};
  std::array<uint64_t, 3> bytes{};
  void fetch(Stream s, uint64_t /*addr*/, uint32_t n) {
    ++fetches[static_cast<int>(s)];
    bytes[static_cast<int>(s)] += n;
  }
};

class HostBackend final : public TraceBackend {
 public:
  explicit HostBackend(const MemoryImage& image) : image_(image) {}
  void trace(std::span<const RayRecord> rays, std::span<Hit> hits) override;
  const MemoryImage* replay_image() const override { return &image_; }
  void replay(const FetchLog& log) override;
  std::unique_ptr<TraceBackend> fork() const override {
    return std::make_unique<HostBackend>(image_);
  }
  void join(const TraceBackend& copy) override;
  const FetchCounts& counts() const { return counts_; }

 private:
  const MemoryImage& image_;
  FetchCounts counts_;
};

}  // namespace rtusim
