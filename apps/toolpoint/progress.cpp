// toolpoint CLI: the progress bar (see progress.hpp). Times in seconds.
#include "progress.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fmt/format.h>
#include <sys/ioctl.h>
#include <unistd.h>

namespace toolpoint::cli {

namespace {

// Work shorter than the delay never shows a bar (TOOLPOINT_PROGRESS_DELAY overrides it);
// redraws are at least kRedrawS apart.
constexpr double kDefaultDelayS = 1.0;
constexpr double kRedrawS = 0.1;
constexpr double kLineEveryS = 5.0;  // without a terminal: a line this often (and not before)

double delay_s(double fallback) {
  const char* text = std::getenv("TOOLPOINT_PROGRESS_DELAY");
  if (text == nullptr) return fallback;
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  return end != text && *end == '\0' && std::isfinite(v) && v >= 0.0 ? v : fallback;
}

Progress* g_shown = nullptr;  // the bar owning the terminal line (one at a time)

int terminal_columns() {
  winsize w{};
  if (::ioctl(STDERR_FILENO, TIOCGWINSZ, &w) == 0 && w.ws_col >= 20) return w.ws_col;
  return 80;
}

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

}  // namespace

std::string progress_line(const std::string& label, double fraction, double elapsed_s, int columns) {
  fraction = std::clamp(fraction, 0.0, 1.0);
  std::string tail = fmt::format(" {:3.0f} %  {:.0f} s", 100.0 * fraction, std::floor(elapsed_s));
  // A remaining-time guess only once there is something to extrapolate from.
  if (fraction >= 0.02 && fraction < 1.0)
    tail += fmt::format(", about {:.0f} s left", std::ceil(elapsed_s * (1.0 - fraction) / fraction));
  // One column is kept free: writing the last one makes some terminals wrap.
  const int room = columns - 1 - static_cast<int>(tail.size());
  std::string name = label;
  int bar = std::min(30, room - static_cast<int>(name.size()) - 3);  // " [" + "]"
  if (bar < 10) {
    bar = std::max(0, std::min(10, room - 3));
    name.resize(static_cast<std::size_t>(std::max(0, room - bar - 3)));
  }
  const int full = static_cast<int>(std::floor(fraction * bar));
  return fmt::format("{} [{}{}]{}", name, std::string(static_cast<std::size_t>(full), '#'),
                     std::string(static_cast<std::size_t>(bar - full), '.'), tail);
}

Progress::Progress(const Globals& g, std::string label)
    : enabled_(!g.quiet && g_shown == nullptr),
      terminal_(::isatty(STDERR_FILENO) == 1),
      label_(std::move(label)),
      delay_s_(delay_s(terminal_ ? kDefaultDelayS : kLineEveryS)),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {
  if (enabled_) g_shown = this;
}

Progress::~Progress() {
  done();
  if (g_shown == this) g_shown = nullptr;
}

void Progress::update(double fraction) {
  if (!enabled_ || std::isnan(fraction)) return;
  fraction_ = std::clamp(fraction, 0.0, 1.0);
  if (!terminal_) {
    if (seconds_since(start_) >= delay_s_ && (!lines_written_ || seconds_since(last_draw_) >= kLineEveryS)) line();
    return;
  }
  if (seconds_since(start_) < delay_s_ || (drawn_ && seconds_since(last_draw_) < kRedrawS)) return;
  draw();
}

void Progress::stage(std::string label, double fraction) {
  label_ = std::move(label);
  if (!enabled_ || std::isnan(fraction)) return;
  fraction_ = std::clamp(fraction, 0.0, 1.0);
  if (!terminal_) {
    update(fraction);
    return;
  }
  if (seconds_since(start_) >= delay_s_) draw();  // a new stage shows at once, unthrottled
}

std::function<void(double)> Progress::part(double from, double to) {
  return [this, from, to](double f) { update(from + (to - from) * std::clamp(f, 0.0, 1.0)); };
}

void Progress::done() {
  if (g_shown == this) clear_line();
  if (enabled_ && lines_written_) {
    std::fputs(fmt::format("{}: done in {:.0f} s\n", label_, std::floor(seconds_since(start_))).c_str(), stderr);
    std::fflush(stderr);
    lines_written_ = false;
  }
}

void Progress::line() {
  const double elapsed = seconds_since(start_);
  std::string text = fmt::format("{}: {:.0f} % after {:.0f} s", label_, std::floor(100.0 * fraction_), std::floor(elapsed));
  if (fraction_ >= 0.02 && fraction_ < 1.0)
    text += fmt::format(", about {:.0f} s left", std::ceil(elapsed * (1.0 - fraction_) / fraction_));
  std::fputs((text + "\n").c_str(), stderr);
  std::fflush(stderr);
  lines_written_ = true;
  last_draw_ = std::chrono::steady_clock::now();
}

void Progress::clear_line() {
  if (g_shown == nullptr || !g_shown->drawn_) return;
  std::fputs("\r\033[K", stderr);  // carriage return, erase to the end of the line
  std::fflush(stderr);
  g_shown->drawn_ = false;
}

void Progress::draw() {
  const std::string line = progress_line(label_, fraction_, seconds_since(start_), terminal_columns());
  std::fputs(("\r" + line + "\033[K").c_str(), stderr);
  std::fflush(stderr);
  drawn_ = true;
  last_draw_ = std::chrono::steady_clock::now();
}

}  // namespace toolpoint::cli
