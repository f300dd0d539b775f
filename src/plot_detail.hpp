// toolpoint: what the plot module's sources share (src/plot_*.cpp): the house style's constants and
// the small helpers for gnuplot text, numbers and argument checks. Private to the library.
#pragma once

#include <cmath>
#include <cstddef>
#include <iterator>
#include <limits>
#include <string>
#include <string_view>

#include <fmt/format.h>

#include "toolpoint/error.hpp"
#include "toolpoint/plot.hpp"

namespace toolpoint::plot::detail {

inline constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// House style: Okabe–Ito colours ordered so that neighbours also differ in lightness, with a dash
// pattern and an open marker per series so that grayscale prints stay readable.
inline constexpr const char* kColours[] = {"#000000", "#D55E00", "#0072B2", "#009E73",
                                           "#CC79A7", "#E69F00", "#56B4E9", "#7F7F7F"};
inline constexpr const char* kDashes[] = {"solid", "(10,6)", "(2,4)", "(10,4,2,4)", "(20,6)", "(6,3,2,3,2,3)", "(5,5)", "(2,2)"};
inline constexpr int kPoints[] = {6, 4, 8, 12, 10, 2, 1, 14};
inline constexpr std::size_t kSeries = std::size(kColours);
inline constexpr const char* kFillColours[] = {"#D3EAD3", "#D6E4F2", "#F4E0D0", "#E8E8E8"};
inline constexpr const char* kBandColour = "#E2E2E2";
inline constexpr const char* kFont = "DejaVu Sans";
inline constexpr int kFontPt = 16;

// Layout in pixels, converted to screen fractions per figure so margins do not grow with size.
inline constexpr double kLeftPx = 130, kRightPx = 30, kTopPx = 25, kTitlePx = 55, kBottomPx = 80, kGapPx = 24;
// Average advance of a DejaVu Sans character, as a fraction of the font size, to size legends.
inline constexpr double kCharEm = 0.68;
inline constexpr int kSampleChars = 4;  // legend sample length, in gnuplot character widths
// What an outside legend needs beside its text: the sample (4 of gnuplot's character widths, ~70
// px at 16 pt) and the gaps around it, measured on pngcairo output.
inline constexpr double kKeyFixedPx = 115;

// A gnuplot double-quoted string.
inline std::string gp_text(std::string_view text) {
  std::string s = "\"";
  for (char c : text) {
    if (c == '\\' || c == '"') s += '\\';
    if (c == '\n') {
      s += "\\n";
      continue;
    }
    s += c;
  }
  s += '"';
  return s;
}

// A gnuplot single-quoted string (no escapes; '' is a quote): for file names.
inline std::string gp_path(std::string_view text) {
  std::string s = "'";
  for (char c : text) s += c == '\'' ? std::string("''") : std::string(1, c);
  s += '\'';
  return s;
}

inline std::string number(double v) { return fmt::format("{}", v); }

inline std::string title_of(const std::string& label) { return label.empty() ? "notitle" : "title " + gp_text(label); }

inline bool plottable(double v, Scale scale) { return std::isfinite(v) && (scale == Scale::Linear || v > 0.0); }

inline void require(bool ok, const std::string& what, const std::string& hint = {}) {
  if (!ok) throw InvalidArgument(what, hint);
}

inline void check_size(int width_px, int height_px) {
  require(width_px >= 200 && width_px <= 20000 && height_px >= 200 && height_px <= 20000,
          fmt::format("figure size {}×{} px is outside 200…20000 px", width_px, height_px));
}

}  // namespace toolpoint::plot::detail
