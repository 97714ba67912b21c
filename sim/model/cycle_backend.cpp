#include "model/cycle_backend.h"

#include <stdexcept>

#include <systemc>

#include "mem/dram/dram.h"
#include "mem/l1_cache.h"
#include "mem/node_l1.h"
#include "model/host_interface.h"
#include "model/traversal_unit.h"
#include "util/stat_decl.h"
#include "util/stats.h"
#include "util/vcd_writer.h"

namespace rtusim {
namespace {
// Stats keys of the cycle tier's top.
const StatDecl kCycles("sim.cycles", StatKind::kCounter, "cycles",
                       "simulated cycles of the unit's clock");
const StatDecl kRaysPerSecond("sim.rays_per_second", StatKind::kRatio, "rays/s",
                              "rays per second of simulated time");
const StatDecl kDramGbps("dram.gbytes_per_second", StatKind::kRatio, "GB/s",
                         "DRAM bytes per second of simulated time");
const StatDecl kUtilisation("unit.utilisation", StatKind::kRatio, "steps/cycle",
                            "traversal steps per cycle");
}  // namespace


struct CycleBackend::Top : sc_core::sc_module {
  HostInterface host;
  Dram dram;
  std::unique_ptr<NodeL1> node_l1;  // l1.model: L1Cache or the RTL adapter
  std::unique_ptr<L1Cache> data_cache;
  TraversalUnit unit;  // last: destroyed first; the memories above hold a pointer to its flag

  Top(const sc_core::sc_module_name& name, const MemoryImage& image, const CycleParams& p)
      : sc_module(name),
        host("host"),
        dram("dram", p.dram),
        node_l1(make_node_l1(p.node_l1_model, "l1", p.node_l1, p.vcd_path)),
        unit("unit", p.unit, image, host) {
    unit.node_socket.bind(node_l1->upstream());
    node_l1->downstream().bind(dram.target_socket);
    node_l1->set_downstream_horizon(&dram);
    unit.add_horizon(&dram);
    if (const MemoryHorizon* h = node_l1->horizon()) unit.add_horizon(h);
    if (p.data_cache) {
      data_cache = std::make_unique<L1Cache>("dcache", *p.data_cache);
      unit.data_socket.bind(data_cache->target_socket);
      data_cache->initiator_socket.bind(dram.target_socket);
      data_cache->set_downstream_horizon(&dram);
      unit.add_horizon(data_cache->horizon());
    } else {
      unit.data_socket.bind(dram.target_socket);
    }
    // The C++ caches and the DRAM also take reads and give answers by direct call (no socket,
    // no sc_time per request).
    auto* node_cpp = dynamic_cast<L1Cache*>(node_l1.get());
    if (node_cpp) node_cpp->set_downstream_direct(&dram);
    if (data_cache) data_cache->set_downstream_direct(&dram);
    unit.set_direct_targets(node_cpp, data_cache ? static_cast<DirectTarget*>(data_cache.get())
                                                 : &dram);
  }
};

namespace {
CycleParams derived(CycleParams p) {
  p.derive();
  return p;
}
// A new SystemC context, made current, for one backend's top.
sc_core::sc_simcontext* fresh_context() {
  auto* context = new sc_core::sc_simcontext;
  sc_core::sc_curr_simcontext = context;
  sc_core::sc_default_global_context = context;
  return context;
}
}  // namespace

CycleBackend::CycleBackend(const MemoryImage& image, const CycleParams& params)
    : params_(derived(params)),
      context_(fresh_context()),
      top_(std::make_unique<Top>("rtu", image, params_)) {
  if (!params_.vcd_path.empty() && params_.node_l1_model == "cpp") {
    vcd_ = std::make_unique<VcdWriter>(params_.vcd_path, "unit");
    top_->unit.set_vcd(vcd_.get());
  }
}

// The context is left alive: SystemC 2.3's kernel keeps process handles that may still refer
// to it after its modules are gone, and it is a few kilobytes per backend.
CycleBackend::~CycleBackend() { top_.reset(); }

void CycleBackend::finish() {
  if (vcd_) vcd_->commit();
  top_->node_l1->finish();
}

void CycleBackend::make_current() const {
  sc_core::sc_curr_simcontext = context_;
  sc_core::sc_default_global_context = context_;
}

void CycleBackend::trace(std::span<const RayRecord> rays, std::span<Hit> hits) {
  if (rays.empty()) return;
  make_current();
  top_->host.post(rays, hits);
  sc_core::sc_start();
  if (const std::exception_ptr e = top_->unit.take_error()) std::rethrow_exception(e);
  if (!top_->host.batch_done())
    throw std::logic_error("cycle backend: the simulation stopped before the batch was done");
  rays_ += rays.size();
}

uint64_t CycleBackend::cycles() const {
  return context_->time_stamp().value() / params_.unit.clock_period_ps;
}
const NodeL1& CycleBackend::node_l1() const { return *top_->node_l1; }
const L1Cache* CycleBackend::data_cache() const { return top_->data_cache.get(); }
const Dram& CycleBackend::dram() const { return top_->dram; }
const TraversalUnit& CycleBackend::unit() const { return top_->unit; }

void CycleBackend::write_stats(Stats& stats) const {
  const uint64_t c = cycles();
  // The clock's period is whole picoseconds (sim.clock_mhz rounded): its seconds, not the MHz's.
  const double seconds = double(c) / (1e12 / double(params_.unit.clock_period_ps));
  stats.set("sim.cycles", c);
  stats.set("sim.rays_per_second", seconds > 0 ? double(rays_) / seconds : 0.0);
  const DramBackend& d = top_->dram.backend();
  d.write_stats(stats, "dram");
  const uint64_t total = d.bytes(Stream::kNode) + d.bytes(Stream::kList) + d.bytes(Stream::kTriangle);
  stats.set("dram.gbytes_per_second", seconds > 0 ? double(total) / seconds / 1e9 : 0.0);
  top_->node_l1->write_stats(stats, "l1");
  if (top_->data_cache) top_->data_cache->write_stats(stats, "dcache");
  top_->unit.write_stats(stats);
  stats.set("unit.utilisation", c ? double(top_->unit.steps()) / double(c) : 0.0);
  stats.set("traversal.node_fetches", top_->unit.steps());
}

}  // namespace rtusim
