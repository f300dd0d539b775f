// The figure model's colour map (plot.hpp: Map, ColourBar): what Figure::check refuses, what the
// gnuplot script holds, and that gnuplot draws it. Used by the plan's stable-depth map and meant
// for a probability-of-stability map over speed × depth.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <unistd.h>

#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/plot/plot.hpp"

using namespace toolpoint;

namespace {

// z = x·y on 4 × 3 cells, one cell NaN.
plot::Figure map_figure() {
  plot::Figure f;
  f.x.label = "Spindle speed [rpm]";
  plot::Panel p;
  p.y.label = "Depth [mm]";
  plot::Map m;
  m.x = {1000.0, 2000.0, 3000.0, 4000.0};
  m.y = {0.5, 1.0, 1.5};
  for (double y : m.y)
    for (double x : m.x) m.z.push_back(x * y);
  m.z[5] = std::numeric_limits<double>::quiet_NaN();
  m.colour = {"Probability of stability [-]", plot::Scale::Linear, 0.0, 6000.0};
  p.map = m;
  p.curves.push_back({{1000.0, 4000.0}, {0.5, 1.5}, "a line on top", plot::CurveStyle::Line, -1});
  f.panels.push_back(p);
  return f;
}

}  // namespace

TEST(PlotMap, CheckRefusesUnevenGridsWrongSizesAndLogAxes) {
  EXPECT_NO_THROW(map_figure().check());
  plot::Figure f = map_figure();
  f.panels[0].map->x[2] = 2900.0;
  EXPECT_THROW(f.check(), InvalidArgument);
  f = map_figure();
  f.panels[0].map->z.pop_back();
  EXPECT_THROW(f.check(), InvalidArgument);
  f = map_figure();
  f.x.scale = plot::Scale::Log;
  EXPECT_THROW(f.check(), InvalidArgument);
  f = map_figure();
  f.panels[0].map->colour.max = -1.0;  // below its min
  EXPECT_THROW(f.check(), InvalidArgument);
  // A map alone is something to draw.
  f = map_figure();
  f.panels[0].curves.clear();
  EXPECT_NO_THROW(f.check());
}

// The cells as `x y z` rows (y blocks), NaN left as NaN; the image under the curves; the colour
// bar with its range, label and place right of the panel; the x range out to the cells' edges.
TEST(PlotMap, ScriptDrawsTheImageUnderTheCurvesWithAColourBar) {
  const std::string s = plot::gnuplot_script(map_figure());
  EXPECT_NE(s.find("$p0m << EOD\n1000 0.5 500\n2000 0.5 1000\n"), std::string::npos) << s;
  EXPECT_NE(s.find("2000 1 NaN\n"), std::string::npos);
  EXPECT_NE(s.find("4000 0.5 2000\n\n1000 1 1000\n"), std::string::npos);  // a blank line between rows
  const std::size_t image = s.find("$p0m using 1:2:3 with image"), curve = s.find("$p0c0 using 1:2");
  ASSERT_NE(image, std::string::npos);
  EXPECT_LT(image, curve);
  EXPECT_NE(s.find("set cbrange [0:6000]"), std::string::npos);
  EXPECT_NE(s.find("set cblabel \"Probability of stability [-]\" offset"), std::string::npos);
  EXPECT_NE(s.find("set colorbox user origin screen"), std::string::npos);
  EXPECT_NE(s.find("set xrange [500:4500]"), std::string::npos) << "cells are centred on their x";
  EXPECT_NE(s.find("set yrange [0.25:1.75]"), std::string::npos);
}

TEST(PlotMap, GnuplotRendersIt) {
  const std::string file =
      (std::filesystem::temp_directory_path() / ("toolpoint_map_" + std::to_string(::getpid()) + ".png")).string();
  try {
    plot::render(map_figure(), file);
  } catch (const plot::PlotUnavailable& e) {
    GTEST_SKIP() << e.what();
  }
  const std::string png = read_text_file(file);
  std::filesystem::remove(file);
  ASSERT_GT(png.size(), 1000u);
  EXPECT_EQ(png.compare(1, 3, "PNG"), 0);
}
