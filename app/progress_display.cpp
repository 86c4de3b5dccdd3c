#include "progress_display.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace {

// "12 s", "3 min 20 s", "1 h 05 min".
std::string duration(double s) {
  if (s < 60.0) return fmt::format("{:.0f} s", s);
  const auto whole = static_cast<long long>(std::lround(s));
  if (whole < 3600) return fmt::format("{} min {:02} s", whole / 60, whole % 60);
  return fmt::format("{} h {:02} min", whole / 3600, (whole % 3600) / 60);
}

std::string json_string(std::string_view text) {
  std::string out = "\"";
  for (const char ch : text) {
    if (ch == '"' || ch == '\\') {
      out += '\\';
      out += ch;
    } else if (static_cast<unsigned char>(ch) < 0x20) {
      out += fmt::format("\\u{:04x}", static_cast<int>(ch));
    } else {
      out += ch;
    }
  }
  return out + "\"";
}

}  // namespace

ProgressStyle progress_style(const std::string& flag, bool quiet) {
  if (quiet) return ProgressStyle::none;
  if (flag == "json") return ProgressStyle::json;
  if (flag == "plain") return ProgressStyle::plain;
  if (flag == "bar") return ProgressStyle::bar;
  return isatty(fileno(stderr)) ? ProgressStyle::bar : ProgressStyle::plain;
}

double eta_seconds(double fraction, double stage_seconds) {
  // Too early to say: the first percent of a stage is mostly its set-up.
  if (!(fraction >= 0.01) || stage_seconds < 0.5) return -1.0;
  if (fraction >= 1.0) return 0.0;
  return stage_seconds * (1.0 - fraction) / fraction;
}

double smoothed_eta(double previous, double seconds_since, double raw, double tau) {
  if (raw < 0.0) return previous;
  if (previous < 0.0) return raw;
  const double counted_down = std::max(0.0, previous - std::max(0.0, seconds_since));
  const double w = 1.0 - std::exp(-std::max(0.0, seconds_since) / tau);
  return counted_down + w * (raw - counted_down);
}

void ProgressDisplay::operator()(const poreshell::Progress& p) {
  switch (style_) {
    case ProgressStyle::none:
      return;
    case ProgressStyle::bar:
      bar(p);
      return;
    case ProgressStyle::json:
      json(p);
      return;
    case ProgressStyle::plain: {
      if (p.step == 0) return;
      const bool energy = p.message.find("energy") != std::string_view::npos;
      if (p.step != 1 && p.step % 10 != 0 && !energy) return;
      fmt::print(stderr, "{}  {:.1f} s\n", p.message, p.seconds);
      return;
    }
  }
}

constexpr int kWidth = 24;  // the bar's characters

void ProgressDisplay::bar(const poreshell::Progress& p) {
  const bool new_stage = p.stage != stage_;
  if (new_stage) {
    if (line_open_)  // the stage just ended: its line at 100% with the time it took
      fmt::print(stderr, "\r  {:<6} [{}] 100%  {}\x1b[K\n", stage_, std::string(kWidth, '#'),
                 duration(p.seconds - stage_start_));
    line_open_ = false;
    stage_ = p.stage;
    stage_start_ = p.seconds;
    eta_ = -1.0;
  }
  // Redrawn at most ten times a second (the solve reports every step).
  const auto now = std::chrono::steady_clock::now();
  if (!new_stage && p.fraction < 1.0 && now - last_draw_ < std::chrono::milliseconds(100)) return;
  last_draw_ = now;
  const double f = std::clamp(p.fraction, 0.0, 1.0);
  const auto filled = static_cast<int>(std::lround(f * kWidth));
  const double elapsed = p.seconds - stage_start_;
  // Damped over a quarter of the stage so far (half a second to 20 s): a short stage's first guesses
  // are soon forgotten, a long one's swings are evened out.
  eta_ =
      smoothed_eta(eta_, p.seconds - eta_at_, eta_seconds(f, elapsed), std::clamp(0.25 * elapsed, 0.5, 20.0));
  eta_at_ = p.seconds;
  std::string line = fmt::format("\r  {:<6} [{}{}] {:3.0f}%  {}", stage_, std::string(filled, '#'),
                                 std::string(kWidth - filled, '.'), 100.0 * f, duration(elapsed));
  if (eta_ >= 0.0 && f < 1.0) {
    line += ", about " + duration(eta_) + " left";
    // The whole run's, from its estimate, where that says more than the stage's.
    if (const double run_left = run_seconds_ - p.seconds; run_left > eta_ + 1.0)
      line += " (the run about " + duration(run_left) + ")";
  }
  if (p.step > 0) line += fmt::format("  (step {})", p.step);
  line += "\x1b[K";  // clear what a longer earlier line left
  fmt::print(stderr, "{}", line);
  std::fflush(stderr);
  line_open_ = true;
}

void ProgressDisplay::json(const poreshell::Progress& p) {
  const double elapsed = p.stage == stage_ ? p.seconds - stage_start_ : 0.0;
  if (p.stage != stage_) {
    stage_ = p.stage;
    stage_start_ = p.seconds;
  }
  const double eta = eta_seconds(p.fraction, elapsed);
  std::string line = fmt::format(R"({{"stage": {}, "fraction": {:.4f}, "seconds": {:.3f}, "eta": )",
                                 json_string(p.stage), p.fraction, p.seconds);
  line += eta >= 0.0 ? fmt::format("{:.1f}", eta) : std::string("null");
  if (p.step > 0) line += fmt::format(R"(, "step": {})", p.step);
  if (!p.message.empty()) line += R"(, "message": )" + json_string(p.message);
  fmt::print(stderr, "{}}}\n", line);
  std::fflush(stderr);
}

void ProgressDisplay::finish() {
  if (line_open_) fmt::print(stderr, "\n");  // as it stood: the run ended or failed there
  line_open_ = false;
}
