#include "rtl_l1_sc.h"

#include <verilated.h>
#if VM_TRACE
#include <verilated_vcd_sc.h>
#endif

#include "rtl/rtl_l1_registry.h"
#include "rtl_l1_sc_models.h"  // generated: the model headers and RTUSIM_RTL_L1_MODELS(X)

namespace rtusim {

namespace {

template <class M>
std::unique_ptr<sc_core::sc_module> bind(const char* name, sc_core::sc_signal_in_if<bool>& clk,
                                         RtlL1Signals& s) {
  auto m = std::make_unique<M>(name);
  m->clk(clk);
  m->rst_n(s.rst_n);
  m->i_req_valid(s.i_req_valid);
  m->o_req_ready(s.o_req_ready);
  m->i_req_addr(s.i_req_addr);
  m->i_req_id(s.i_req_id);
  m->o_req_hit(s.o_req_hit);
  m->o_req_merged(s.o_req_merged);
  m->o_req_mshr(s.o_req_mshr);
  m->o_resp_valid(s.o_resp_valid);
  m->i_resp_ready(s.i_resp_ready);
  m->o_resp_id(s.o_resp_id);
  m->o_mem_req_valid(s.o_mem_req_valid);
  m->i_mem_req_ready(s.i_mem_req_ready);
  m->o_mem_req_addr(s.o_mem_req_addr);
  m->i_mem_resp_valid(s.i_mem_resp_valid);
  m->i_mem_resp_addr(s.i_mem_resp_addr);
  m->o_fill_valid(s.o_fill_valid);
  m->o_fill_mshr(s.o_fill_mshr);
  m->o_mshrs_busy(s.o_mshrs_busy);
  return m;
}

#if VM_TRACE
std::unique_ptr<VerilatedVcdSc> g_vcd;

template <class M>
bool trace(sc_core::sc_module& module, const std::string& path) {
  auto* m = dynamic_cast<M*>(&module);
  if (!m) return false;
  Verilated::traceEverOn(true);
  g_vcd = std::make_unique<VerilatedVcdSc>();
  m->trace(g_vcd.get(), 99);
  g_vcd->open(path.c_str());
  return true;
}
#endif

}  // namespace

std::unique_ptr<sc_core::sc_module> make_rtl_l1(const char* name, const CacheParams& p,
                                                sc_core::sc_signal_in_if<bool>& clk,
                                                RtlL1Signals& s) {
  const RtlL1Build& b = rtl_l1_build(p);
#define RTUSIM_MAKE(M) \
  if (b.model == #M) return bind<M>(name, clk, s);
  RTUSIM_RTL_L1_MODELS(RTUSIM_MAKE)
#undef RTUSIM_MAKE
  throw std::logic_error("rtl_l1: registry lists " + std::string(b.model) +
                         " but no such model is linked");
}

bool open_rtl_l1_vcd([[maybe_unused]] sc_core::sc_module& module,
                     [[maybe_unused]] const std::string& path) {
#if VM_TRACE
#define RTUSIM_TRACE(M) \
  if (trace<M>(module, path)) return true;
  RTUSIM_RTL_L1_MODELS(RTUSIM_TRACE)
#undef RTUSIM_TRACE
#endif
  return false;
}

void close_rtl_l1_vcd() {
#if VM_TRACE
  if (g_vcd) {
    g_vcd->close();
    g_vcd.reset();
  }
#endif
}

}  // namespace rtusim
