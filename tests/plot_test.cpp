// Tests of the plot module. The rendered files are checked against their format specifications
// (PNG signature and IHDR chunk, SVG well-formed XML with an <svg> root and its size, PDF header,
// trailer and MediaBox), not against the code that wrote them; peak finding is checked against
// closed-form resonance frequencies; the figure builders against the values they were given.
// Every figure kind is rendered once per format with small data, to keep the suite fast.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <vector>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/plot/plot.hpp"
#include "support/scratch.hpp"

using namespace toolpoint;
using namespace toolpoint::plot;
namespace fs = std::filesystem;

namespace {

// A fresh folder per test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    std::string tmpl = (fs::temp_directory_path() / "toolpoint_plot_XXXXXX").string();
    if (::mkdtemp(tmpl.data()) == nullptr) throw std::runtime_error("mkdtemp failed");
    path_ = tmpl;
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string operator/(const std::string& leaf) const { return (path_ / leaf).string(); }
  const fs::path& path() const { return path_; }
  // Everything in the folder, hidden temporaries included.
  std::vector<std::string> entries() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(path_)) out.push_back(e.path().filename().string());
    return out;
  }

 private:
  fs::path path_;
};

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A small XML well-formedness check: tags nest and match, attributes are quoted, entity
// references are complete, there is exactly one root element. Returns the root's name and its
// attributes, or throws std::runtime_error saying where the document breaks.
struct XmlRoot {
  std::string name;
  std::vector<std::pair<std::string, std::string>> attributes;
};

XmlRoot parse_xml(const std::string& doc) {
  std::vector<std::string> open;
  XmlRoot root;
  bool root_seen = false;
  std::size_t i = 0;
  auto fail = [&](const std::string& why) { throw std::runtime_error(why + " at byte " + std::to_string(i)); };
  auto is_name = [](char c) {
    return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == ':' || c == '-' || c == '.';
  };
  auto check_text = [&](std::size_t from, std::size_t to) {
    for (std::size_t k = from; k < to; ++k) {
      if (doc[k] != '&') continue;
      const std::size_t semi = doc.find(';', k);
      if (semi == std::string::npos || semi > to || semi == k + 1) fail("bad entity reference");
      for (std::size_t q = k + 1; q < semi; ++q)
        if (!is_name(doc[q]) && doc[q] != '#') fail("bad entity reference");
    }
  };
  while (i < doc.size()) {
    if (doc[i] != '<') {
      const std::size_t next = doc.find('<', i);
      const std::size_t end = next == std::string::npos ? doc.size() : next;
      if (open.empty())
        for (std::size_t k = i; k < end; ++k)
          if (!std::isspace(static_cast<unsigned char>(doc[k]))) fail("text outside the root element");
      check_text(i, end);
      i = end;
      continue;
    }
    auto skip_to = [&](const std::string& close) {
      const std::size_t end = doc.find(close, i);
      if (end == std::string::npos) fail("unterminated " + close);
      i = end + close.size();
    };
    if (doc.compare(i, 4, "<!--") == 0) {
      skip_to("-->");
      continue;
    }
    if (doc.compare(i, 9, "<![CDATA[") == 0) {
      if (open.empty()) fail("CDATA outside root");
      skip_to("]]>");
      continue;
    }
    if (doc.compare(i, 2, "<?") == 0) {
      skip_to("?>");
      continue;
    }
    if (doc.compare(i, 2, "<!") == 0) {
      skip_to(">");
      continue;
    }  // DOCTYPE (no internal subset here)
    const bool closing = doc.compare(i, 2, "</") == 0;
    i += closing ? 2 : 1;
    const std::size_t name_start = i;
    while (i < doc.size() && is_name(doc[i])) ++i;
    const std::string name = doc.substr(name_start, i - name_start);
    if (name.empty()) fail("missing tag name");
    if (closing) {
      while (i < doc.size() && std::isspace(static_cast<unsigned char>(doc[i]))) ++i;
      if (i >= doc.size() || doc[i] != '>') fail("bad end tag");
      ++i;
      if (open.empty() || open.back() != name) fail("end tag </" + name + "> does not match");
      open.pop_back();
      continue;
    }
    if (open.empty() && root_seen) fail("second root element <" + name + ">");
    std::vector<std::pair<std::string, std::string>> attrs;
    for (;;) {
      while (i < doc.size() && std::isspace(static_cast<unsigned char>(doc[i]))) ++i;
      if (i >= doc.size()) fail("unterminated tag <" + name + ">");
      if (doc[i] == '>' || doc.compare(i, 2, "/>") == 0) break;
      const std::size_t a = i;
      while (i < doc.size() && is_name(doc[i])) ++i;
      if (i == a) fail("bad attribute in <" + name + ">");
      const std::string key = doc.substr(a, i - a);
      while (i < doc.size() && std::isspace(static_cast<unsigned char>(doc[i]))) ++i;
      if (i >= doc.size() || doc[i] != '=') fail("attribute " + key + " without value");
      ++i;
      while (i < doc.size() && std::isspace(static_cast<unsigned char>(doc[i]))) ++i;
      if (i >= doc.size() || (doc[i] != '"' && doc[i] != '\'')) fail("unquoted attribute " + key);
      const char q = doc[i++];
      const std::size_t end = doc.find(q, i);
      if (end == std::string::npos || doc.find('<', i) < end) fail("bad attribute value for " + key);
      check_text(i, end);
      attrs.emplace_back(key, doc.substr(i, end - i));
      i = end + 1;
    }
    const bool empty = doc[i] == '/';
    i += empty ? 2 : 1;
    if (open.empty()) {
      root_seen = true;
      root = {name, attrs};
    }
    if (!empty) open.push_back(name);
  }
  if (!open.empty()) throw std::runtime_error("unclosed element <" + open.back() + ">");
  if (!root_seen) throw std::runtime_error("no root element");
  return root;
}

std::string attribute(const XmlRoot& r, const std::string& key) {
  for (const auto& [k, v] : r.attributes)
    if (k == key) return v;
  return {};
}

// Checks a rendered file by its format, at the size the figure asked for.
void expect_valid(const std::string& path, Format format, int width, int height) {
  ASSERT_TRUE(fs::exists(path)) << path;
  const std::string bytes = slurp(path);
  // A figure with axes, labels and data is tens of kB in every format; an empty canvas is ~1 kB.
  EXPECT_GT(bytes.size(), 5000u) << path;
  switch (format) {
    case Format::Png: {
      const auto [w, h] = test::png_size(bytes);
      EXPECT_EQ(w, static_cast<unsigned>(width)) << path;
      EXPECT_EQ(h, static_cast<unsigned>(height)) << path;
      break;
    }
    case Format::Svg: {
      XmlRoot root;
      ASSERT_NO_THROW(root = parse_xml(bytes)) << path;
      EXPECT_EQ(root.name, "svg");
      EXPECT_EQ(attribute(root, "width"), std::to_string(width)) << path;
      EXPECT_EQ(attribute(root, "height"), std::to_string(height)) << path;
      break;
    }
    case Format::Pdf: {
      EXPECT_EQ(bytes.compare(0, 7, "%PDF-1."), 0) << path;
      EXPECT_NE(bytes.find("%%EOF", bytes.size() - 32), std::string::npos) << path;
      // 72 px per inch: the page is as many points as the PNG is pixels.
      EXPECT_NE(bytes.find("/MediaBox [ 0 0 " + std::to_string(width) + " " + std::to_string(height) + " ]"), std::string::npos)
          << path;
      break;
    }
  }
}

// Renders to PNG and SVG (and PDF when asked) and checks each file.
void render_everywhere(const Figure& fig, const std::string& stem, bool pdf = false) {
  TempDir dir;
  std::vector<std::pair<std::string, Format>> targets = {{".png", Format::Png}, {".svg", Format::Svg}};
  if (pdf) targets.push_back({".pdf", Format::Pdf});
  for (const auto& [ext, format] : targets) {
    const std::string path = dir / (stem + ext);
    const RenderResult r = render(fig, path);
    EXPECT_EQ(r.format, format);
    EXPECT_TRUE(r.warnings.empty()) << stem << ext << ": " << (r.warnings.empty() ? "" : r.warnings.front());
    expect_valid(path, format, fig.width_px, fig.height_px);
  }
  EXPECT_EQ(dir.entries().size(), targets.size()) << "temporary files left behind";
}

// Sum of single-degree-of-freedom modes (f_n [Hz], ζ, k [N/m]): H = Σ 1/(k(1 − r² + 2iζr)).
FrfSeries modes_frf(const std::vector<double>& fn, double zeta, double k, double f0, double f1, double df) {
  FrfSeries s;
  for (double f = f0; f <= f1 + 1e-9; f += df) {
    Complex h = 0.0;
    for (double n : fn) {
      const double r = f / n;
      h += 1.0 / (k * Complex(1.0 - r * r, 2.0 * zeta * r));
    }
    s.frequency_hz.push_back(f);
    s.values.push_back(h);
  }
  return s;
}

std::vector<double> magnitudes(const FrfSeries& s) {
  std::vector<double> m;
  for (const Complex& v : s.values) m.push_back(std::abs(v));
  return m;
}

}  // namespace

// ---- Peak finding ---------------------------------------------------------------------------------

// A single mode: |H| peaks at f_n sqrt(1 − 2ζ²) (closed form). On a 1 Hz grid the index found
// must be that frequency rounded to the grid (±1 Hz: the discrete maximum can sit on either side).
TEST(Plot, PeakOfSingleModeIsAtDampedResonance) {
  const double fn = 1234.5, zeta = 0.03;
  const FrfSeries s = modes_frf({fn}, zeta, 1e7, 500.0, 2500.0, 1.0);
  const auto peaks = peak_indices(magnitudes(s), 5, 2.0);
  ASSERT_EQ(peaks.size(), 1u);
  EXPECT_NEAR(s.frequency_hz[peaks[0]], fn * std::sqrt(1.0 - 2.0 * zeta * zeta), 1.0);
}

// Three well-separated light modes give three peaks in frequency order; asking for two keeps the
// two most prominent. 1 % multiplicative noise must not add peaks at a 6 dB prominence
// threshold. Tolerance 1 % of f_n: near a peak |H| ≈ H_max (1 − (δ/ζ)²/2) for a relative offset
// δ, so noise swings of 2 × 3σ = 6 % can move the sampled maximum by δ = 0.35 ζ = 0.7 %.
TEST(Plot, PeaksOfSeveralModesIgnoreNoise) {
  FrfSeries s = modes_frf({800.0, 2100.0, 4300.0}, 0.02, 1e7, 100.0, 6000.0, 2.0);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(1.0, 0.01);
  for (Complex& v : s.values) v *= noise(rng);
  const auto m = magnitudes(s);
  const auto peaks = peak_indices(m, 10, 2.0);
  ASSERT_EQ(peaks.size(), 3u);
  const double fn[] = {800.0, 2100.0, 4300.0};
  for (int k = 0; k < 3; ++k) EXPECT_NEAR(s.frequency_hz[peaks[k]], fn[k], 0.01 * fn[k]) << k;
  const auto two = peak_indices(m, 2, 2.0);
  ASSERT_EQ(two.size(), 2u);
  // Mode 1's higher base is the static level at 100 Hz (|H| rises from there to the peak); the
  // others sit between antiresonances or above the low high-frequency tail, so they are kept.
  EXPECT_TRUE(two[0] < two[1]);
  for (std::size_t p : two) EXPECT_GT(s.frequency_hz[p], 1000.0);
}

// Ends are not peaks, a plateau counts once at its middle, and bad arguments are refused.
TEST(Plot, PeakEdgeCases) {
  EXPECT_TRUE(peak_indices({5.0, 1.0, 1.0, 5.0}, 3, 1.5).empty());
  const auto plateau = peak_indices({1.0, 4.0, 4.0, 4.0, 1.0}, 3, 1.5);
  ASSERT_EQ(plateau.size(), 1u);
  EXPECT_EQ(plateau[0], 2u);
  EXPECT_TRUE(peak_indices({1.0, 1.2, 1.0}, 3, 1.5).empty());  // ratio 1.2 < 1.5
  EXPECT_THROW(peak_indices({1.0}, -1, 2.0), InvalidArgument);
  EXPECT_THROW(peak_indices({1.0}, 1, 1.0), InvalidArgument);
}

// ---- The figure model -------------------------------------------------------------------------------

TEST(Plot, FormatFromExtension) {
  EXPECT_EQ(format_for_path("a/b.png"), Format::Png);
  EXPECT_EQ(format_for_path("B.SVG"), Format::Svg);
  EXPECT_EQ(format_for_path("c.Pdf"), Format::Pdf);
  EXPECT_THROW(format_for_path("figure.jpg"), InvalidArgument);
  EXPECT_THROW(format_for_path("figure"), InvalidArgument);
}

TEST(Plot, BadFiguresAreRefused) {
  Figure empty;
  EXPECT_THROW(empty.check(), InvalidArgument);
  Figure f;
  f.panels.push_back({});
  f.panels[0].curves.push_back({{1.0, 2.0}, {1.0}, "short y", CurveStyle::Line, -1});
  EXPECT_THROW(f.check(), InvalidArgument);
  f.panels[0].curves[0].y = {1.0, 2.0};
  EXPECT_NO_THROW(f.check());
  f.panels[0].y.scale = Scale::Log;
  f.panels[0].y.min = 0.0;  // a log axis cannot start at 0
  EXPECT_THROW(f.check(), InvalidArgument);
  f.panels[0].y.min.reset();
  f.panels[0].curves[0].y = {-1.0, 0.0};  // nothing drawable on a log axis
  EXPECT_THROW(f.check(), InvalidArgument);
  f.panels[0].y.scale = Scale::Linear;
  f.x.min = 5.0;
  f.x.max = 1.0;
  EXPECT_THROW(f.check(), InvalidArgument);
  f.x = {};
  f.width_px = 10;
  EXPECT_THROW(f.check(), InvalidArgument);
}

// Panels share the x axis: with no limits given, every panel gets the union of all panels' x
// data, so they line up even when their own data differ. Non-finite points break the line
// (a blank line in the data block) instead of being written.
TEST(Plot, ScriptSharesXRangeAndBreaksAtNonFinite) {
  Figure f;
  Panel a, b;
  a.curves.push_back({{2.0, 3.0, 4.0}, {1.0, std::nan(""), 2.0}, "a", CurveStyle::Line, -1});
  b.curves.push_back({{1.0, 6.0}, {1.0, 2.0}, "b", CurveStyle::Line, -1});
  f.panels = {a, b};
  const std::string s = gnuplot_script(f);
  std::size_t count = 0;
  for (std::size_t at = s.find("set xrange [1:6]"); at != std::string::npos; at = s.find("set xrange [1:6]", at + 1)) ++count;
  EXPECT_EQ(count, 2u) << s;
  EXPECT_NE(s.find("$p0c0 << EOD\n2 1\n\n4 2\nEOD\n"), std::string::npos) << s;
}

// The layout the renderer decides (issue 26: titles clipped at the figure's edges, legends over
// the data, labels through the title or on each other, a colour scale saturating unsaid). Each is
// judged from the script against the geometry it sets: the ranges, the corner, the labels kept.
namespace {

// The text of the first `set <what> ...` line of a script, or "".
std::string line_of(const std::string& s, const std::string& start) {
  const std::size_t at = s.find(start);
  return at == std::string::npos ? std::string() : s.substr(at, s.find('\n', at) - at);
}

std::size_t count_of(const std::string& s, const std::string& part) {
  std::size_t n = 0;
  for (std::size_t at = s.find(part); at != std::string::npos; at = s.find(part, at + 1)) ++n;
  return n;
}

}  // namespace

// A title far wider than the figure is broken into lines (at spaces or after '/'), each holding
// at most as many characters as the width allows at the widest glyph a file name uses ('m',
// 0.974 em of 18 pt at 4/3 px per pt: 23.4 px) … and at least what the narrowest could (none is
// cut mid-word when a space is near); a short title stays one line.
TEST(PlotLayout, ALongTitleIsBrokenToFitTheWidth) {
  Figure f;
  f.width_px = 600;
  Panel p;
  p.curves.push_back({{1.0, 2.0}, {1.0, 2.0}, "a", CurveStyle::Line, -1});
  f.panels = {p};
  f.title = "Tool point FRF from /a/very/long/folder/name/for/the/measured/holder/data/sh11_filtered.csv + model tool (Eq. 5)";
  const std::string title = line_of(gnuplot_script(f), "set multiplot title ");
  ASSERT_FALSE(title.empty());
  EXPECT_GE(count_of(title, "\\n"), 1u) << title;
  // Each line: not wider than the figure at any glyph's width (0.278 em, 'l', the narrowest used).
  std::size_t start = title.find('"') + 1;
  for (std::size_t end; (end = title.find("\\n", start)) != std::string::npos || start < title.size(); start = end + 2) {
    if (end == std::string::npos) end = title.rfind('"');
    const std::string line = title.substr(start, end - start);
    EXPECT_LE(static_cast<double>(line.size()) * 0.278 * 18.0 * 4.0 / 3.0, 600.0) << line;
    if (end == title.rfind('"')) break;
  }
  f.title = "Short";
  EXPECT_EQ(count_of(line_of(gnuplot_script(f), "set multiplot title "), "\\n"), 0u);
}

// The legend goes where it covers no data: a curve filling the top right leaves it the top left;
// a curve filling the top half leaves it a bottom corner; noise over the whole frame sends it
// outside (a key at screen coordinates, the panels narrowed). The default was top right always.
TEST(PlotLayout, TheLegendKeepsOffTheData) {
  const auto key_of = [](const std::vector<double>& x, const std::vector<double>& y) {
    Figure f;
    Panel p;
    p.curves.push_back({x, y, "data", CurveStyle::Line, -1});
    f.panels = {p};
    return line_of(gnuplot_script(f), "set key ");
  };
  std::vector<double> x, rising, high, noise;
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i <= 400; ++i) {
    x.push_back(i);
    rising.push_back(i < 300 ? 0.0 : (i - 300) / 10.0);  // 0 until x = 300, then up to 10 at the right edge
    high.push_back(i == 0 ? 0.0 : i % 2 ? 10.0 : 5.0);   // from 0, then a zig-zag over the upper half
    noise.push_back(u(rng));
  }
  EXPECT_NE(key_of(x, rising).find("set key top left"), std::string::npos) << key_of(x, rising);
  EXPECT_NE(key_of(x, high).find("set key bottom"), std::string::npos) << key_of(x, high);
  EXPECT_NE(key_of(x, noise).find("set key at screen"), std::string::npos) << key_of(x, noise);
}

// Labels: of two at one point only the first is drawn; one at the top of an autoscaled panel gets
// room above it (the range raised so that the text, 1.1 lines above the point, stays inside);
// on a panel with an explicit top, a label that would cross it is left out.
TEST(PlotLayout, LabelsNeitherOverlapNorLeaveTheFrame) {
  Figure f;
  Panel p;
  p.curves.push_back({{0.0, 5.0, 10.0}, {0.0, 10.0, 0.0}, "", CurveStyle::Line, -1});
  p.labels = {{5.0, 10.0, "peak", true}, {5.0, 10.0, "again", true}};
  f.panels = {p};
  std::string s = gnuplot_script(f);
  EXPECT_EQ(count_of(s, "set label \"peak\""), 1u) << s;
  EXPECT_EQ(count_of(s, "set label \"again\""), 0u) << s;
  const std::string range = line_of(s, "set yrange [");
  const double top = std::stod(range.substr(range.find(':') + 1));
  // 700 px high, one panel of 700 − 25 − 80 px: the label's top (1.7 lines of ~26 px above the
  // point) needs the point at most ~(1 − 48/595) of the range: top ≥ 10.9.
  EXPECT_GE(top, 10.8) << range;
  f.panels[0].y.max = 10.0;
  s = gnuplot_script(f);
  EXPECT_EQ(count_of(s, "set label \"peak\""), 0u) << s;
}

// A colour bar ending below the data's maximum (a percentile, so a few high cells do not darken
// the rest) says so: its top tic reads "≥ 2" and no plain tic crowds it; a bar covering the data
// keeps gnuplot's own tics.
TEST(PlotLayout, ASaturatedColourBarSaysSo) {
  Figure f;
  Panel p;
  Map m;
  m.x = {0.0, 1.0, 2.0};
  m.y = {0.0, 1.0};
  m.z = {0.0, 0.5, 1.0, 1.5, 2.0, 9.0};
  m.colour.label = "Depth [mm]";
  m.colour.min = 0.0;
  m.colour.max = 2.0;
  p.map = m;
  f.panels = {p};
  const std::string tics = line_of(gnuplot_script(f), "set cbtics (");
  EXPECT_NE(tics.find("\"≥ 2\" 2"), std::string::npos) << tics;
  EXPECT_EQ(tics.find("\"2\" 2"), std::string::npos) << tics;
  f.panels[0].map->colour.max = 9.0;
  EXPECT_EQ(gnuplot_script(f).find("set cbtics ("), std::string::npos);
}

// literal() makes enhanced-text markup print verbatim: in the SVG the file name must appear as
// one piece of text (gnuplot would otherwise set "T11.csv" as a subscript in its own element).
TEST(Plot, LiteralTextSurvivesEnhancedMode) {
  EXPECT_EQ(literal("a_b^c{d}@&~\\"), "a\\_b\\^c\\{d\\}\\@\\&\\~\\\\");
  Figure f;
  f.title = literal("tool_T11.csv");
  f.x.label = "Frequency [Hz]";
  Panel p;
  p.y.label = "k_{yf} [N/m]";
  p.curves.push_back({{1.0, 2.0, 3.0}, {1.0, 4.0, 9.0}, "", CurveStyle::Line, -1});
  f.panels = {p};
  TempDir dir;
  render(f, dir / "t.svg");
  const std::string svg = slurp(dir / "t.svg");
  EXPECT_NE(svg.find("tool_T11.csv"), std::string::npos);
  EXPECT_EQ(svg.find("k_{yf}"), std::string::npos);  // markup, not text
}

// ---- Ready-made figures: content ------------------------------------------------------------------

// Magnitude and phase in degrees from the complex values (independent: known values), the
// phase line broken where it wraps through ±180°, and the first peak labelled with its frequency.
TEST(Plot, FrfFigureMagnitudePhase) {
  FrfSeries s;
  s.frequency_hz = {10.0, 20.0, 30.0, 40.0, 50.0};
  s.values = {Complex(0, -2e-6), Complex(-1e-6, 1e-8), Complex(-1e-6, -1e-8), Complex(3e-6, 0), Complex(1e-6, 0)};
  FrfFigureOptions o;
  o.symbol = "H_{11}";
  o.mode_labels = 3;
  o.min_peak_ratio = 1.5;
  const Figure f = frf_figure({{s, "measured", CurveStyle::Line}}, o);
  ASSERT_EQ(f.panels.size(), 2u);
  EXPECT_EQ(f.panels[0].y.label, "|H_{11}| [m/N]");
  EXPECT_EQ(f.panels[0].y.scale, Scale::Log);
  EXPECT_NEAR(f.panels[0].curves[0].y[0], 2e-6, 1e-21);
  const Curve& ph = f.panels[1].curves[0];
  // −90°, break, ~179.4°, break, ~−179.4°, 0°, 0°: a jump of more than 180° between samples is
  // a wrap (−90° → −180.6° here, then −180.6° → −179.4° + … ), so the line breaks twice.
  ASSERT_EQ(ph.y.size(), 7u);
  EXPECT_NEAR(ph.y[0], -90.0, 1e-12);
  EXPECT_TRUE(std::isnan(ph.y[1]));
  EXPECT_NEAR(ph.y[2], 180.0 - std::atan(0.01) * 180.0 / kPi, 1e-9);
  EXPECT_TRUE(std::isnan(ph.y[3]));
  EXPECT_NEAR(ph.y[4], -180.0 + std::atan(0.01) * 180.0 / kPi, 1e-9);
  EXPECT_NEAR(ph.y[5], 0.0, 1e-12);
  // |H| = 2, 1, 1, 3, 1 (×1e-6): one interior peak, at 40 Hz.
  ASSERT_EQ(f.panels[0].labels.size(), 1u);
  EXPECT_EQ(f.panels[0].labels[0].x, 40.0);
  EXPECT_EQ(f.panels[0].labels[0].text, "40 Hz");
  // Peaks are sought only in the plotted range.
  o.frequency_range_hz = {{10.0, 35.0}};
  EXPECT_TRUE(frf_figure({{s, "measured", CurveStyle::Line}}, o).panels[0].labels.empty());
}

// Re/Im of a receptance in µm/N: the curve holds the input times 1e6 and the unit says µm/N.
TEST(Plot, FrfFigureRealImaginaryUsesAnSiPrefix) {
  const FrfSeries s = modes_frf({1000.0}, 0.05, 1e7, 500.0, 1500.0, 10.0);
  FrfFigureOptions o;
  o.view = FrfView::RealImaginary;
  o.mode_labels = 1;
  const Figure f = frf_figure({{s, "", CurveStyle::Points}}, o);
  EXPECT_EQ(f.panels[0].y.label, "Re H [µm/N]");
  EXPECT_EQ(f.panels[1].y.label, "Im H [µm/N]");
  for (std::size_t k = 0; k < s.size(); k += 17) {
    EXPECT_NEAR(f.panels[0].curves[0].y[k], s.values[k].real() * 1e6, 1e-12 * std::abs(s.values[k]) * 1e6);
    EXPECT_NEAR(f.panels[1].curves[0].y[k], s.values[k].imag() * 1e6, 1e-12 * std::abs(s.values[k]) * 1e6);
  }
  ASSERT_EQ(f.panels[0].vertical_lines.size(), 1u);
  EXPECT_NEAR(f.panels[0].vertical_lines[0].x, 1000.0, 10.0);  // one grid step
}

// Identified parameters: scaled to MN/m with the reference line scaled alike; a spike 1e5 times
// the level (an ill-conditioned frequency) is left outside the robust y range, which still holds
// the reference line and the bulk of the values.
TEST(Plot, JointFigureScalesAndClipsSpikes) {
  JointFigureData d;
  JointParameterCurve yf;
  yf.name = "yf";
  yf.stiffness_unit = "N/m";
  yf.damping_unit = "N·s/m";
  for (int k = 0; k < 200; ++k) {
    d.frequency_hz.push_back(100.0 + 10.0 * k);
    yf.stiffness.push_back(k == 50 ? 1.5e12 : 1.5e7 * (1.0 + 0.01 * std::sin(k)));
    yf.damping.push_back(120.0);
  }
  yf.reference_stiffness = 1.6e7;
  yf.identified_damping = 118.0;
  d.parameters = {yf};
  d.band_hz = {{500.0, 900.0}};
  const Figure f = joint_figure(d);
  ASSERT_EQ(f.panels.size(), 2u);  // k panel, then c panel
  const Panel& k = f.panels[0];
  EXPECT_EQ(k.y.label, "k_{yf} [MN/m]");
  EXPECT_NEAR(k.curves[0].y[0], 15.0, 1e-9);
  ASSERT_EQ(k.horizontal_lines.size(), 1u);
  EXPECT_NEAR(k.horizontal_lines[0].y, 16.0, 1e-9);
  ASSERT_TRUE(k.y.min && k.y.max);
  EXPECT_LT(*k.y.max, 100.0);        // the 1.5e6 MN/m spike is off the panel
  EXPECT_GT(*k.y.max, 16.0);         // the reference line is on it
  EXPECT_LT(*k.y.min, 15.0 * 0.99);  // and so is the band's data
  ASSERT_EQ(k.bands.size(), 1u);
  EXPECT_EQ(f.panels[1].y.label, "c_{yf} [N·s/m]");  // 120: no prefix needed
  EXPECT_EQ(f.panels[1].horizontal_lines.at(0).y, 118.0);
  EXPECT_TRUE(f.panels[1].bands.at(0).label.empty());  // the band is named once
}

// Lobes: depths shown in mm, the stable region filled under the envelope down to 0, lobe
// numbers at interior minima only, the envelope drawn last (on top).
TEST(Plot, LobesFigureContent) {
  LobesFigureData d;
  for (int n = 0; n < 3; ++n) {
    Lobe l;
    l.number = n;
    for (int k = 0; k <= 20; ++k) {
      const double centre = 20000.0 / (n + 1), u = (k - 10) / 10.0;
      l.spindle_speed_rpm.push_back(centre * (1.0 + 0.3 * u));
      l.depth_m.push_back(n == 2 ? 1e-3 * (1.0 + u) : 1e-4 * (1.0 + 4.0 * u * u));  // lobe 2: minimum at its end
      l.chatter_frequency_hz.push_back(900.0 + 10.0 * k);
    }
    d.lobes.push_back(l);
  }
  d.envelope_rpm = {5000.0, 10000.0, 20000.0};
  d.envelope_depth_m = {2e-4, 1e-4, 1e-4};
  const Figure f = lobes_figure(d);
  ASSERT_EQ(f.panels.size(), 2u);
  EXPECT_EQ(f.x.min.value_or(0.0), 5000.0);  // the speed axis spans the envelope
  EXPECT_EQ(f.x.max.value_or(0.0), 20000.0);
  const Panel& p = f.panels[0];
  EXPECT_EQ(p.y.label, "Axial depth of cut [mm]");
  EXPECT_NEAR(*p.y.max, 0.5, 1e-12);  // default top: 5 × the envelope's 0.1 mm minimum
  ASSERT_EQ(p.fills.size(), 1u);
  EXPECT_EQ(p.fills[0].base, 0.0);
  EXPECT_NEAR(p.fills[0].y[0], 0.2, 1e-12);
  ASSERT_EQ(p.labels.size(), 2u);
  EXPECT_EQ(p.labels[0].text, "0");
  EXPECT_NEAR(p.labels[0].y, 0.1, 1e-12);
  EXPECT_EQ(p.labels[1].text, "1");
  EXPECT_EQ(p.curves.back().label, "stability limit");
  EXPECT_EQ(f.panels[1].y.label, "Chatter frequency [Hz]");
}

// Lobe numbers never overlap (issue 13: "11" and "13" printed as "113"). Lobes of two modes,
// 920 Hz and 2600 Hz, 40 each, interleave at low speed at nearly the same depth. The bound is
// physical, not the figure's own rule: a 16 pt digit is about 10 px of an ~850 px panel, so two
// numbers on about one line (within 5 % of the depth axis) need their centres at least half their
// widths apart, 1.2 % of the speed range per digit. Lobe 0 of each mode is kept.
TEST(PlotFigures, LobeNumbersNeverOverlap) {
  LobesFigureData d;
  for (const double fc : {920.0, 2600.0})
    for (int n = 0; n < 40; ++n) {
      Lobe l;
      l.number = n + (fc > 1000.0 ? 100 : 0);
      const double bottom = 60.0 * fc / (4.0 * (n + 0.8));
      for (int k = -5; k <= 5; ++k) {
        l.spindle_speed_rpm.push_back(bottom * (1.0 + 0.01 * k / (n + 1.0)));
        l.depth_m.push_back((fc > 1000.0 ? 1.05e-3 : 1e-3) * (1.0 + 0.02 * k * k));
      }
      d.lobes.push_back(l);
    }
  d.envelope_rpm = {2000.0, 40000.0};
  d.envelope_depth_m = {1e-3, 1e-3};
  const Figure f = lobes_figure(d);
  const std::vector<TextLabel>& labels = f.panels[0].labels;
  ASSERT_GE(labels.size(), 2u);
  const double range = *f.x.max - *f.x.min, height = *f.panels[0].y.max - *f.panels[0].y.min;
  for (std::size_t i = 0; i < labels.size(); ++i)
    for (std::size_t j = i + 1; j < labels.size(); ++j) {
      if (std::abs(labels[i].y - labels[j].y) >= 0.05 * height) continue;
      const double need = 0.5 * 0.012 * range * static_cast<double>(labels[i].text.size() + labels[j].text.size());
      EXPECT_GE(std::abs(labels[i].x - labels[j].x), need) << labels[i].text << " and " << labels[j].text;
    }
  const auto has = [&](const std::string& t) {
    return std::any_of(labels.begin(), labels.end(), [&](const TextLabel& l) { return l.text == t; });
  };
  EXPECT_TRUE(has("0"));
  EXPECT_TRUE(has("100"));
}

// ---- Rendering: every figure kind, every format --------------------------------------------------------

TEST(PlotRender, FrfFigures) {
  const FrfSeries measured = modes_frf({1200.0, 3400.0}, 0.02, 1e7, 100.0, 5000.0, 20.0);
  const FrfSeries predicted = modes_frf({1180.0, 3450.0}, 0.025, 1.05e7, 100.0, 5000.0, 20.0);
  FrfFigureOptions o;
  o.title = "Tool point FRF";
  o.symbol = "H_{11}";
  o.mode_labels = 2;
  render_everywhere(frf_figure({{measured, "measured", CurveStyle::Line}, {predicted, "predicted", CurveStyle::Dashed}}, o),
                    "frf", true);
  o.view = FrfView::RealImaginary;
  o.frequency_scale = Scale::Log;
  render_everywhere(frf_figure({{measured, "measured", CurveStyle::Points}, {predicted, "predicted", CurveStyle::Line}}, o),
                    "frf_reim");
}

TEST(PlotRender, ReceptanceAndOverhangFigures) {
  BlockSeries b;
  const FrfSeries h = modes_frf({900.0, 2600.0}, 0.01, 2e6, 50.0, 4000.0, 10.0);
  for (std::size_t k = 0; k < h.size(); ++k) {
    b.frequency_hz.push_back(h.frequency_hz[k]);
    b.blocks.push_back(make_block(h.values[k], 0.1 * h.values[k], 0.1 * h.values[k], 0.02 * h.values[k]));
  }
  const Figure r = receptance_figure(b, "Block T_{11}", "11");
  EXPECT_EQ(r.panels.size(), 4u);
  EXPECT_GT(r.height_px, 700);  // taller for four panels
  render_everywhere(r, "receptance");

  FrfFigureOptions o;
  o.mode_labels = 2;
  render_everywhere(overhang_frf_figure({0.082, 0.088, 0.094},
                                        {modes_frf({1200.0, 3400.0}, 0.02, 1e7, 100.0, 5000.0, 20.0),
                                         modes_frf({1190.0, 3200.0}, 0.02, 1e7, 100.0, 5000.0, 20.0),
                                         modes_frf({1180.0, 3000.0}, 0.02, 1e7, 100.0, 5000.0, 20.0)},
                                        o),
                    "overhang_frf");
  OverhangSweep sweep;
  sweep.overhang_m = {0.070, 0.080, 0.090, 0.100};
  sweep.frequency_hz = {{1900, 1870, 1840, 1800}, {4000, 3420, 2960, 2770}};
  render_everywhere(natural_frequency_figure(sweep), "natural_frequencies");
}

TEST(PlotRender, JointAndLobesFigures) {
  JointFigureData d;
  JointParameterCurve yf{"yf", "N/m", "N·s/m", {}, {}, 1.5e7, 120.0, 1.45e7, 118.0};
  JointParameterCurve tm{"θm", "N·m/rad", "N·m·s/rad", {}, {}, 2.1e5, std::nullopt, std::nullopt, std::nullopt};
  for (int k = 0; k < 300; ++k) {
    d.frequency_hz.push_back(200.0 + 20.0 * k);
    yf.stiffness.push_back(1.45e7 * (1.0 + 0.05 * std::sin(0.7 * k)));
    yf.damping.push_back(118.0 * (1.0 + 0.1 * std::cos(0.3 * k)));
    tm.stiffness.push_back(2e5 * (1.0 + 0.03 * std::sin(1.3 * k)));
  }
  d.parameters = {yf, tm};
  d.band_hz = {{2200.0, 2600.0}};
  d.title = "Holder–tool joint";
  render_everywhere(joint_figure(d), "joint");

  // Data shaped like real lobes: the classic one-mode lobes (Tlusty), a = −1/(2 K_s Re G),
  // ε = 2π − 2 atan(Re G / Im G), n = 60 f_c / (N (k + ε/2π)), for the docs/reference.md §7 mode.
  LobesFigureData L;
  const double fn = 922.0, zeta = 0.011, kx = 1.34e6, Ks = 3e8;
  const int teeth = 2;
  for (int n = 0; n < 4; ++n) {
    Lobe lobe;
    lobe.number = n;
    for (double fc = fn * 1.001; fc < fn * 1.3; fc += 1.0) {
      const double r = fc / fn;
      const Complex G = 1.0 / (kx * Complex(1.0 - r * r, 2.0 * zeta * r));
      const double eps = 2.0 * kPi - 2.0 * std::atan(G.real() / G.imag());
      lobe.spindle_speed_rpm.push_back(60.0 * fc / (teeth * (n + eps / (2.0 * kPi))));
      lobe.depth_m.push_back(-1.0 / (2.0 * Ks * G.real()));
      lobe.chatter_frequency_hz.push_back(fc);
    }
    L.lobes.push_back(lobe);
  }
  for (double rpm = 6000.0; rpm <= 25000.0; rpm += 100.0) {
    double best = INFINITY;
    for (const Lobe& l : L.lobes)
      for (std::size_t q = 1; q < l.spindle_speed_rpm.size(); ++q) {
        const double a = l.spindle_speed_rpm[q - 1], b = l.spindle_speed_rpm[q];
        if ((rpm - a) * (rpm - b) <= 0.0 && a != b)
          best = std::min(best, l.depth_m[q - 1] + (rpm - a) / (b - a) * (l.depth_m[q] - l.depth_m[q - 1]));
      }
    if (std::isfinite(best)) {
      L.envelope_rpm.push_back(rpm);
      L.envelope_depth_m.push_back(best);
    }
  }
  L.title = "Stability lobes";
  render_everywhere(lobes_figure(L), "lobes", true);
}

// ---- Rendering: failures leave nothing behind -------------------------------------------------------

namespace {

Figure tiny_figure() {
  Figure f;
  f.x.label = "x [m]";
  Panel p;
  p.y.label = "y [m]";
  p.curves.push_back({{0.0, 1.0, 2.0, 3.0}, {0.0, 1.0, 4.0, 9.0}, "y = x²", CurveStyle::LinePoints, -1});
  f.panels = {p};
  return f;
}

}  // namespace

// gnuplot's own error message reaches the caller; the target keeps its old content and no
// temporary file is left behind.
TEST(PlotRender, GnuplotErrorIsReportedAndNothingIsWritten) {
  TempDir dir;
  const std::string target = dir / "broken.png";
  write_text_file(target, "old content");
  try {
    render_script("plot sin(x) wiht lines\n", target, 600, 400);
    FAIL() << "no error";
  } catch (const PlotUnavailable&) {
    FAIL() << "a script error is not a missing gnuplot";
  } catch (const IoError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("gnuplot failed"), std::string::npos) << what;
    EXPECT_NE(what.find("wiht"), std::string::npos) << what;  // gnuplot echoes the offending command
  }
  EXPECT_EQ(slurp(target), "old content");
  EXPECT_EQ(dir.entries().size(), 1u);
}

TEST(PlotRender, MissingGnuplotHasItsOwnError) {
  TempDir dir;
  PlotOptions o;
  o.gnuplot = "/nonexistent/gnuplot";
  for (const char* leaf : {"f.png", "f.svg", "f.pdf"}) {
    try {
      render(tiny_figure(), dir / leaf, o);
      FAIL() << "no error";
    } catch (const PlotUnavailable& e) {
      EXPECT_NE(std::string(e.what()).find("gnuplot not found"), std::string::npos) << e.what();
      EXPECT_NE(e.hint().find("gnuplot-nox"), std::string::npos);
    }
  }
  EXPECT_TRUE(dir.entries().empty());
}

// A gnuplot built without cairo is simulated by a wrapper that blanks the terminal list the
// script consults: PNG falls back to the libgd terminal with a note, PDF cannot be made.
TEST(PlotRender, TerminalFallbacks) {
  if (!fs::exists("/bin/sh") || (!fs::exists("/usr/bin/sed") && !fs::exists("/bin/sed"))) GTEST_SKIP() << "no sh/sed";
  TempDir dir;
  const std::string wrapper = dir / "gnuplot-without-cairo";
  write_text_file(wrapper, "#!/bin/sh\nsed 's/GPVAL_TERMINALS/\" svg png \"/' | exec gnuplot \"$@\"\n");
  fs::permissions(wrapper, fs::perms::owner_all);
  PlotOptions o;
  o.gnuplot = wrapper;
  const RenderResult r = render(tiny_figure(), dir / "f.png", o);
  EXPECT_EQ(r.terminal, "png");
  ASSERT_EQ(r.notes.size(), 1u);
  EXPECT_NE(r.notes[0].find("pngcairo"), std::string::npos);
  const auto [w, h] = test::png_size(slurp(dir / "f.png"));
  EXPECT_EQ(w, 1000u);
  EXPECT_EQ(h, 700u);
  EXPECT_THROW(render(tiny_figure(), dir / "f.pdf", o), PlotUnavailable);
  EXPECT_FALSE(fs::exists(dir / "f.pdf"));
  EXPECT_EQ(dir.entries().size(), 2u);  // the wrapper and f.png
}

// gnuplot writing much to stderr while the script is still being fed must not stall either
// side: 8000 lines of output (≈ 150 kB, over twice a 64 kB pipe buffer) ahead of a 250 kB data
// block (ditto). They come back as warnings, since gnuplot succeeded.
TEST(PlotRender, ChattyGnuplotDoesNotDeadlock) {
  std::string body = "do for [i=1:8000] { print sprintf('chatter line %d', i) }\n$big << EOD\n";
  for (int k = 0; k < 25000; ++k) body += std::to_string(k) + " " + std::to_string(k % 97) + "\n";
  body += "EOD\nplot $big using 1:2 with lines\n";
  TempDir dir;
  PlotOptions o;
  o.timeout_s = 60.0;  // a stall would end here, as an IoError, not as a hung test
  const RenderResult r = render_script(body, dir / "chatty.png", 400, 300, o);
  EXPECT_EQ(r.warnings.size(), 8000u);
  EXPECT_EQ(r.warnings.back(), "chatter line 8000");
  EXPECT_EQ(test::png_size(slurp(dir / "chatty.png")).first, 400u);
}

TEST(PlotRender, TimeoutStopsGnuplot) {
  TempDir dir;
  PlotOptions o;
  o.timeout_s = 0.3;
  EXPECT_THROW(render_script("pause 30\nplot x\n", dir / "slow.png", 400, 300, o), IoError);
  EXPECT_TRUE(dir.entries().empty());
}
