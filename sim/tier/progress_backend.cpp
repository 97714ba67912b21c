// Progress bar for long runs.
#include "tier/progress_backend.h"

#include <cstdio>
#include <cstdlib>

#include <unistd.h>

#include "tracer/fetch_log.h"

namespace rtusim {

namespace {
constexpr double kRedrawSeconds = 0.2;

// Runs shorter than this show nothing: 2 s, or $RTUSIM_PROGRESS_QUIET_S (tests set 0, so the
// bar's drawing is checked whatever the machine's speed).
double quiet_seconds() {
  if (const char* env = std::getenv("RTUSIM_PROGRESS_QUIET_S"); env && *env) return std::atof(env);
  return 2.0;
}
}  // namespace

ProgressBackend::ProgressBackend(TraceBackend& inner, uint64_t primary_rays, std::string label)
    : inner_(inner), total_(primary_rays), label_(std::move(label)), enabled_(isatty(2) != 0),
      start_(std::chrono::steady_clock::now()), last_draw_(start_),
      quiet_seconds_(quiet_seconds()) {}

ProgressBackend::~ProgressBackend() {
  if (drawn_) draw(true);
}

void ProgressBackend::trace(std::span<const RayRecord> rays, std::span<Hit> hits) {
  inner_.trace(rays, hits);
  if (!enabled_) return;
  uint64_t primary = 0;
  for (const RayRecord& r : rays) primary += r.kind == RayKind::kPrimary;
  advance(primary);
}

void ProgressBackend::replay(const FetchLog& log) {
  inner_.replay(log);
  if (enabled_) advance(log.ray_count(RayKind::kPrimary));
}

void ProgressBackend::advance(uint64_t primary_rays) {
  done_ += primary_rays;
  const auto now = std::chrono::steady_clock::now();
  if (std::chrono::duration<double>(now - start_).count() < quiet_seconds_ ||
      std::chrono::duration<double>(now - last_draw_).count() < kRedrawSeconds)
    return;
  last_draw_ = now;
  draw(false);
}

void ProgressBackend::draw(bool final) {
  constexpr int kWidth = 30;
  const double f = total_ ? double(done_) / double(total_) : 1.0;
  const int filled = static_cast<int>(f * kWidth);
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::fprintf(stderr, "\r  %-8s [%.*s%*s] %3.0f%% %6.1f s", label_.c_str(), filled,
               "##############################", kWidth - filled, "", 100.0 * f, secs);
  if (final) std::fprintf(stderr, "\n");
  std::fflush(stderr);
  drawn_ = true;
}

}  // namespace rtusim
