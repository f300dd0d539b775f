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

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/plot/plot.hpp"

namespace toolpoint::plot::detail {


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
inline constexpr double kTitleLinePx = 24;  // each further line of a title broken to fit
// The width of text set in DejaVu Sans at `pt` points, in px as pngcairo draws it (96 px per inch:
// 4/3 px per point): each ASCII character's advance from the font's metrics (em fractions), 0.7 em
// for any other code point; gnuplot's enhanced-text markup ({ } _ ^ \) takes no room. Sizes
// legends, labels and titles so that they can be kept off the data and inside the figure.
inline double text_px(std::string_view text, double pt) {
  static constexpr double kAdvance[95] = {0.318, 0.400, 0.460, 0.838, 0.636, 0.950, 0.780, 0.275,
                                          0.390, 0.390, 0.500, 0.838, 0.318, 0.361, 0.318, 0.337,  //  !"#$%&'()*+,-./
                                          0.636, 0.636, 0.636, 0.636, 0.636, 0.636, 0.636, 0.636,
                                          0.636, 0.636, 0.337, 0.337, 0.838, 0.838, 0.838, 0.531,  // 0-9:;<=>?
                                          1.000, 0.684, 0.686, 0.698, 0.770, 0.632, 0.575, 0.775,
                                          0.752, 0.295, 0.295, 0.656, 0.557, 0.863, 0.748, 0.787,  // @A-O
                                          0.603, 0.787, 0.695, 0.635, 0.611, 0.732, 0.684, 0.989,
                                          0.685, 0.611, 0.685, 0.390, 0.337, 0.390, 0.838, 0.500,  // P-Z[\]^_
                                          0.500, 0.613, 0.635, 0.550, 0.635, 0.615, 0.352, 0.635,
                                          0.634, 0.278, 0.278, 0.579, 0.278, 0.974, 0.634, 0.612,  // `a-o
                                          0.635, 0.635, 0.411, 0.521, 0.392, 0.634, 0.592, 0.818,
                                          0.592, 0.592, 0.525, 0.636, 0.337, 0.636, 0.838};  // p-z{|}~
  double em = 0.0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if ((c & 0xC0) == 0x80 || c == '{' || c == '}' || c == '_' || c == '^' || c == '\\') continue;
    em += c >= 32 && c < 127 ? kAdvance[c - 32] : 0.7;
  }
  return em * pt * 4.0 / 3.0;
}
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
