// Traversal of a batch of rays, 8 at a time in a RayPacket where the host has AVX2 (AVX-512
// hosts too: 16 lanes were slower, docs/speed_notes.md), else, and for rays a packet does not
// take, one by one with traverse(). The caller sees exactly what traverse() ray by ray would
// give: every hit bit for bit, and every ray's fetches, ray after ray in batch order.
#pragma once
#include <algorithm>
#include <cstddef>
#include <span>
#include <type_traits>

#include "traversal/fetch_recorder.h"
#include "traversal/ray_packet.h"
#include "traversal/traversal.h"

namespace rtusim {

// A batch sink whose state does not depend on the order of its fetches (counters) may say so
// with `static constexpr bool kFetchOrderFree = true`: packet lanes then report to it directly
// instead of through per-ray buffers.
template <class Sink>
constexpr bool kFetchOrderFree = requires { requires Sink::kFetchOrderFree; };

namespace batch_detail {

// Packet lane sinks (RayPacket::traverse()'s `lanes`) for each kind of batch sink.
struct DroppingLanes {  // NullFetchSink: nothing to report
  static constexpr bool kDropsFetches = true;
  NullFetchSink none;
  NullFetchSink& lane(int) { return none; }
};
template <class Sink>
struct SharedLanes {  // an order-free sink: every lane reports to it as it goes
  static constexpr bool kDropsFetches = false;
  Sink& sink;
  Sink& lane(int) { return sink; }
};
template <int kLanes>
struct BufferedLanes {  // any other sink: each lane's fetches kept until its turn
  static constexpr bool kDropsFetches = false;
  FetchList buffers[kLanes];
  FetchList& lane(int i) { return buffers[i]; }
};

// Ends ray `i` at the sink, if it takes ends.
template <class Sink>
void end_ray(Sink& sink, size_t i) {
  if constexpr (requires { sink.end_ray(i); }) sink.end_ray(i);
}

}  // namespace batch_detail

#if defined(RTUSIM_RAY_PACKETS)
using HostRayPacket = RayPacket;
#else
using HostRayPacket = void;  // no packets: ray by ray
#endif

// traverse_batch() with packets of type `Packet` (a BasicRayPacket; void: none, ray by ray).
template <class Decoder, class Packet, class Record, class Sink>
void traverse_batch_with(const MemoryImage& image, std::span<const Record> rays,
                         std::span<Hit> hits, Sink& sink) {
  size_t begin = 0;
  // Packets of rays [begin, begin + kLanes) in batch order; rays a packet does not take, and
  // groups where fewer than two would share it, go one by one.
  constexpr size_t kMinLanes = 2;
  if constexpr (!std::is_void_v<Packet>) {
    if (rays.size() >= kMinLanes) {
      using Lanes = std::conditional_t<
          std::is_same_v<Sink, NullFetchSink>, batch_detail::DroppingLanes,
          std::conditional_t<kFetchOrderFree<Sink>, batch_detail::SharedLanes<Sink>,
                             batch_detail::BufferedLanes<Packet::kLanes>>>;
      Lanes lanes = [&] {
        if constexpr (std::is_same_v<Lanes, batch_detail::SharedLanes<Sink>>) return Lanes{sink};
        else return Lanes{};
      }();
      Packet packet;
      for (; begin + kMinLanes <= rays.size(); begin += Packet::kLanes) {
        const size_t n = std::min<size_t>(Packet::kLanes, rays.size() - begin);
        uint32_t taken = 0;
        for (size_t i = 0; i < n; ++i)
          if (Packet::admits(rays[begin + i].ray)) taken |= 1u << i;
        if (static_cast<size_t>(__builtin_popcount(taken)) < kMinLanes) {
          for (size_t i = begin; i < begin + n; ++i) {
            hits[i] = traverse<Decoder>(image, rays[i].ray, rays[i].any_hit(), sink);
            batch_detail::end_ray(sink, i);
          }
          continue;
        }
        packet.clear();
        for (uint32_t m = taken; m != 0; m &= m - 1) {
          const int lane = __builtin_ctz(m);
          const Record& r = rays[begin + lane];
          packet.set_lane(lane, image, r.ray, r.any_hit());
        }
        packet.template traverse<Decoder>(image, lanes);
        // Hand out in batch order: a lane's buffered fetches, or a lone ray traced now.
        for (size_t i = 0; i < n; ++i) {
          const size_t at = begin + i;
          if (taken >> i & 1u) {
            hits[at] = packet.hit(static_cast<int>(i));
            if constexpr (std::is_same_v<Lanes, batch_detail::BufferedLanes<Packet::kLanes>>) {
              FetchList& buf = lanes.buffers[i];
              for (size_t k = 0; k < buf.size(); ++k)
                sink.fetch(buf[k].stream, buf[k].addr, buf[k].bytes);
              buf.clear();
            }
          } else {
            hits[at] = traverse<Decoder>(image, rays[at].ray, rays[at].any_hit(), sink);
          }
          batch_detail::end_ray(sink, at);
        }
      }
    }
  }
  for (size_t i = begin; i < rays.size(); ++i) {
    hits[i] = traverse<Decoder>(image, rays[i].ray, rays[i].any_hit(), sink);
    batch_detail::end_ray(sink, i);
  }
}

// Traverses `rays` (records with `.ray` and `.any_hit()`), setting hits[i] to rays[i]'s hit.
// The sink sees rays[i]'s fetches (fetch(stream, addr, bytes), as traverse() reports them), then
// end_ray(i) if it has one, ray after ray in batch order. `Decoder` as in traverse().
template <class Decoder, class Record, class Sink>
void traverse_batch(const MemoryImage& image, std::span<const Record> rays, std::span<Hit> hits,
                    Sink& sink) {
  traverse_batch_with<Decoder, HostRayPacket>(image, rays, hits, sink);
}

}  // namespace rtusim
