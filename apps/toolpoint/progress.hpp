// toolpoint CLI: a progress bar on stderr for work that takes more than a second.
// Units: fractions of the work 0…1, times in seconds.
//
// Library loops report progress through an optional std::function<void(double fraction)>
// (fraction of the work done, 0…1) and never print; this class turns those calls into one line
// on stderr, redrawn in place with '\r':
//     lobes (sd boundary) [##############..............]  48 %  2 s, about 2 s left
// It draws only when stderr is a terminal (isatty) and --quiet is off, and only once the work has
// run for a second (the environment variable TOOLPOINT_PROGRESS_DELAY sets another delay in
// seconds, 0 for at once): quick runs, pipes, logs and tests see nothing. The line is erased when
// the work ends, and before any info()/warn() message, so messages never land on a half line.
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

  bool enabled_ = false;
  std::string label_;
  double delay_s_ = 1.0;
  double fraction_ = 0.0;
  std::chrono::steady_clock::time_point start_, last_draw_;
  bool drawn_ = false;
};

// The line drawn for `label` at `fraction` after `elapsed_s` seconds, fitted to `columns`
// characters (the bar shrinks first, then the label is cut). No '\r', no newline.
std::string progress_line(const std::string& label, double fraction, double elapsed_s, int columns);

}  // namespace toolpoint::cli
