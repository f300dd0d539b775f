// toolpoint CLI: progress on stderr for work that takes more than a moment.
// Units: fractions of the work 0…1, times in seconds.
//
// Library loops report progress through an optional std::function<void(double fraction)>
// (fraction of the work done, 0…1) and never print; this class turns those calls into
//   * on a terminal (isatty), one line redrawn in place with '\r', once the work has run for a
//     second:
//         lobes: full-discretization boundary [##############..............]  48 %  2 s, about 2 s left
//     erased when the work ends, and before any info()/warn() message, so messages never land on
//     a half line;
//   * otherwise (a pipe, a log file, a batch job), a line every 5 s, the first after 5 s, and a
//     closing line when the work ends:
//         lobes: full-discretization boundary: 48 % after 10 s, about 11 s left
//         lobes: full-discretization boundary: done in 21 s
// Nothing with --quiet. The environment variable TOOLPOINT_PROGRESS_DELAY sets the first delay in
// seconds for both (0: at once), so quick runs, pipes and tests normally see nothing.
#pragma once

#include <chrono>
#include <functional>
#include <string>

#include "cli.hpp"

namespace toolpoint::cli {

class Progress {
 public:
  Progress(const Globals& g, std::string label);
  ~Progress();
  Progress(const Progress&) = delete;
  Progress& operator=(const Progress&) = delete;

  // Fraction done, 0…1 (clamped; NaN ignored). Redraws at most 10 times a second.
  void update(double fraction);
  // A new stage of the same work: its name and the fraction done when it starts.
  void stage(std::string label, double fraction);
  // For a library loop covering [from, to] of this bar: its 0…1 maps onto that range.
  std::function<void(double)> part(double from = 0.0, double to = 1.0);
  // Erases the line (also done by the destructor).
  void done();

  // Erases the line of the bar being shown, if any (info() and warn() call it).
  static void clear_line();

 private:
  void draw();

  void line();

  bool enabled_ = false;
  bool terminal_ = false;  // a bar redrawn in place; otherwise lines
  bool lines_written_ = false;
  std::string label_;
  double delay_s_ = 1.0;  // before the bar, or before the first line
  double fraction_ = 0.0;
  std::chrono::steady_clock::time_point start_, last_draw_;
  bool drawn_ = false;
};

// The line drawn for `label` at `fraction` after `elapsed_s` seconds, fitted to `columns`
// characters (the bar shrinks first, then the label is cut). No '\r', no newline.
std::string progress_line(const std::string& label, double fraction, double elapsed_s, int columns);

}  // namespace toolpoint::cli
