// The Verilated C++ l1_cache builds behind the RtlL1Model interface.
#include <cstdlib>
#include <stdexcept>

#include <verilated.h>
#if VM_TRACE
#include <verilated_vcd_c.h>
#endif

#include "rtl_l1_cpp_models.h"  // generated: model headers and RTUSIM_RTL_L1_CPP_MODELS(X)
#include "rtl_l1_harness.h"

namespace rtusim::rtltest {

namespace {

template <class M>
class Model final : public RtlL1Model {
 public:
  Model() : ctx_(std::make_unique<VerilatedContext>()), m_(std::make_unique<M>(ctx_.get())) {
    if (const char* vcd = std::getenv("RTUSIM_RTL_VCD")) open_vcd(vcd);
    m_->clk = 0;
    reset();
  }
  ~Model() override {
    m_->final();
#if VM_TRACE
    if (vcd_) vcd_->close();
#endif
  }

  void drive(const Inputs& in) override {
    m_->rst_n = in.rst_n;
    m_->i_req_valid = in.req_valid;
    m_->i_req_addr = in.req_addr;
    m_->i_req_id = in.req_id;
    m_->i_resp_ready = in.resp_ready;
    m_->i_mem_req_ready = in.mem_req_ready;
    m_->i_mem_resp_valid = in.mem_resp_valid;
    m_->i_mem_resp_addr = in.mem_resp_addr;
    m_->eval();
  }
  Outputs outputs() const override {
    Outputs o;
    o.req_ready = m_->o_req_ready;
    o.req_hit = m_->o_req_hit;
    o.req_merged = m_->o_req_merged;
    o.req_mshr = m_->o_req_mshr;
    o.resp_valid = m_->o_resp_valid;
    o.resp_id = m_->o_resp_id;
    o.mem_req_valid = m_->o_mem_req_valid;
    o.mem_req_addr = m_->o_mem_req_addr;
    o.fill_valid = m_->o_fill_valid;
    o.fill_mshr = m_->o_fill_mshr;
    o.mshrs_busy = m_->o_mshrs_busy;
    return o;
  }
  void posedge() override {
    m_->clk = 1;
    m_->eval();
    dump();
    m_->clk = 0;
    m_->eval();
    ++cycles_;
    dump();
  }
  void reset() override {
    Inputs in;
    in.rst_n = false;
    drive(in);
    posedge();
    posedge();
    in.rst_n = true;
    drive(in);
  }

  void replay_blocking(std::span<const uint64_t> addrs, std::vector<Outcome>& out) override {
    M& m = *m_;
    m.i_resp_ready = 1;
    m.i_mem_req_ready = 1;
    m.i_mem_resp_valid = 0;
    out.reserve(out.size() + addrs.size());
    for (const uint64_t addr : addrs) {
      const uint32_t id = next_id_++ & 0xffffu;
      m.i_req_valid = 1;
      m.i_req_addr = addr;
      m.i_req_id = id;
      m.eval();
      if (!m.o_req_ready) throw std::runtime_error("rtl_l1: request not ready in blocking mode");
      const Outcome o = m.o_req_hit      ? Outcome::kHit
                        : m.o_req_merged ? Outcome::kMergedMiss
                                         : Outcome::kPrimaryMiss;
      const uint32_t mshr = m.o_req_mshr;
      out.push_back(o);
      posedge();  // accepts the request (and takes the previous hit's response)
      m.i_req_valid = 0;
      m.eval();
      if (o == Outcome::kHit) {
        if (!m.o_resp_valid || m.o_resp_id != id)
          throw std::runtime_error("rtl_l1: no response, or one for another id, after a hit");
        if (m.o_mem_req_valid) throw std::runtime_error("rtl_l1: a line read for a hit");
        continue;
      }
      if (!m.o_mem_req_valid) throw std::runtime_error("rtl_l1: no line read for a miss");
      const uint64_t line = m.o_mem_req_addr;
      ++memory_requests_;
      posedge();  // memory takes the read
      m.i_mem_resp_valid = 1;
      m.i_mem_resp_addr = line;
      m.eval();
      if (!m.o_fill_valid || m.o_fill_mshr != mshr)
        throw std::runtime_error("rtl_l1: the fill frees another MSHR than the miss's");
      posedge();  // the fill frees the MSHR
      m.i_mem_resp_valid = 0;
      m.eval();
      if (m.o_mshrs_busy != 0) throw std::runtime_error("rtl_l1: an MSHR busy after its fill");
    }
  }

  uint64_t cycles() const override { return cycles_; }
  uint64_t memory_requests() const override { return memory_requests_; }

  bool open_vcd([[maybe_unused]] const std::string& path) override {
#if VM_TRACE
    ctx_->traceEverOn(true);
    vcd_ = std::make_unique<VerilatedVcdC>();
    m_->trace(vcd_.get(), 99);
    vcd_->open(path.c_str());
    return true;
#else
    return false;
#endif
  }

 private:
  void dump() {
#if VM_TRACE
    if (vcd_) vcd_->dump(static_cast<uint64_t>(2 * cycles_ + m_->clk));
#endif
  }

  std::unique_ptr<VerilatedContext> ctx_;
  std::unique_ptr<M> m_;
#if VM_TRACE
  std::unique_ptr<VerilatedVcdC> vcd_;
#endif
  uint64_t cycles_ = 0, memory_requests_ = 0;
  uint32_t next_id_ = 0;
};

}  // namespace

const std::vector<std::string>& cpp_model_names() {
  static const std::vector<std::string> names = {
#define RTUSIM_NAME(M) #M,
      RTUSIM_RTL_L1_CPP_MODELS(RTUSIM_NAME)
#undef RTUSIM_NAME
  };
  return names;
}

std::unique_ptr<RtlL1Model> make_cpp_model(const std::string& registry_model) {
  // The C++ builds are named "Vc" + the SystemC build's stem: "Vl1_..." -> "Vcl1_...".
  const std::string name = "Vc" + registry_model.substr(1);
#define RTUSIM_MAKE(M) \
  if (name == #M) return std::make_unique<Model<M>>();
  RTUSIM_RTL_L1_CPP_MODELS(RTUSIM_MAKE)
#undef RTUSIM_MAKE
  return nullptr;
}

}  // namespace rtusim::rtltest
