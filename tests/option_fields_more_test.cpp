// The option tables migrated after LobesStudyOptions (option_fields.hpp; issue 26): each Options
// type's check() against the ranges its fields had before the tables, written out here by hand from
// the old check()s and headers (not read from the table), so that a table that drifts from them
// fails. For each field: a value just outside each edge of its range is refused with an
// InvalidArgument naming `Options::field`, a value at (or just inside) each edge is accepted. The
// CLI's flags: cli_option_fields_more_test.cpp; Python's: python/tests/test_option_fields_more.py.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "toolpoint/error.hpp"
#include "toolpoint/measured/signal.hpp"
#include "toolpoint/conventions.hpp"
#include "toolpoint/option_fields.hpp"
#include "toolpoint/studies/precision.hpp"
#include "toolpoint/studies/tap_test.hpp"

using namespace toolpoint;

namespace {

// One field's edges: the values check() accepts and refuses, each set on valid options.
template <class Options>
struct Edges {
  const char* field;
  std::function<void(Options&, double)> set;
  std::vector<double> accepted, refused;
};

// check() on `valid` with each value set: accepted ones pass, refused ones throw InvalidArgument
// whose message names `name::field`.
template <class Options>
void expect_edges(const Options& valid, const std::string& name, const std::vector<Edges<Options>>& edges) {
  ASSERT_NO_THROW(valid.check());
  for (const Edges<Options>& e : edges) {
    for (double v : e.accepted) {
      Options o = valid;
      e.set(o, v);
      EXPECT_NO_THROW(o.check()) << e.field << " = " << v;
    }
    for (double v : e.refused) {
      Options o = valid;
      e.set(o, v);
      try {
        o.check();
        ADD_FAILURE() << e.field << " = " << v << " accepted";
      } catch (const InvalidArgument& x) {
        EXPECT_NE(std::string(x.what()).find(name + "::" + e.field), std::string::npos) << x.what();
      }
    }
  }
}

// The fields a table holds, by name.
template <class Options>
std::set<std::string> names_of(const std::vector<OptionField<Options>>& fields) {
  std::set<std::string> names;
  for (const OptionField<Options>& f : fields) names.insert(f.spec.name);
  return names;
}

// A tiny step past an edge: 1e-12 relative (or absolute at 0), far above an ulp, far below any
// value a user means.
double above(double v) { return v == 0.0 ? 1e-12 : v * (1.0 + 1e-12); }
double below(double v) { return v == 0.0 ? -1e-12 : v * (1.0 - 1e-12); }

}  // namespace

// NoiseOptions (signal.hpp): σ ≥ 0 and finite; floor in [0, 0.5]; calibration in [0, 0.1];
// averages 0 or 2…10000.
TEST(OptionFieldsMore, NoiseOptionsRanges) {
  EXPECT_EQ(names_of(noise_fields()), (std::set<std::string>{"sigma", "floor", "calibration", "averages"}));
  using O = NoiseOptions;
  expect_edges<O>(O{}, "NoiseOptions",
                  {{"sigma", [](O& o, double v) { o.sigma = v; }, {0.0, 10.0}, {below(0.0), kNaN, kInf}},
                   {"floor", [](O& o, double v) { o.floor = v; }, {0.0, 0.5}, {below(0.0), above(0.5), kNaN}},
                   {"calibration", [](O& o, double v) { o.calibration = v; }, {0.0, 0.1}, {below(0.0), above(0.1), kNaN}},
                   {"averages", [](O& o, double v) { o.averages = static_cast<int>(v); }, {0, 2, 10000}, {-1, 1, 10001}}});
}

// TapTestOptions (tap_test.hpp): spacing_m > 0 and finite; points 2 or 3; σ in [0, 1); floor,
// calibration and averages as NoiseOptions' (named TapTestOptions::…).
TEST(OptionFieldsMore, TapTestOptionsRanges) {
  EXPECT_EQ(names_of(tap_test_fields()),
            (std::set<std::string>{"spacing_m", "points", "sigma", "floor", "averages", "calibration"}));
  using O = TapTestOptions;
  O valid;
  valid.spacing_m = 0.01;
  expect_edges<O>(valid, "TapTestOptions",
                  {{"spacing_m", [](O& o, double v) { o.spacing_m = v; }, {1e-12, 0.01}, {0.0, -1e-12, kNaN, kInf}},
                   {"points", [](O& o, double v) { o.points = static_cast<int>(v); }, {2, 3}, {1, 4}},
                   {"sigma", [](O& o, double v) { o.sigma = v; }, {0.0, below(1.0)}, {below(0.0), 1.0, kNaN}},
                   {"floor", [](O& o, double v) { o.floor = v; }, {0.0, 0.5}, {below(0.0), above(0.5), kNaN}},
                   {"calibration", [](O& o, double v) { o.calibration = v; }, {0.0, 0.1}, {below(0.0), above(0.1)}},
                   {"averages", [](O& o, double v) { o.averages = static_cast<int>(v); }, {0, 2, 10000}, {-1, 1, 10001}}});
}

// TapNoise (precision.hpp): σ and floor in [0, 0.5] (not both 0: a check of its own, on a base with
// both nonzero here), averages 1…100000, calibration in [0, 0.1]; shared_calibration either way.
TEST(OptionFieldsMore, TapNoiseRanges) {
  EXPECT_EQ(names_of(tap_noise_fields()),
            (std::set<std::string>{"sigma", "floor", "averages", "calibration", "shared_calibration"}));
  using O = TapNoise;
  O valid;
  valid.floor = 0.001;
  expect_edges<O>(valid, "TapNoise",
                  {{"sigma", [](O& o, double v) { o.sigma = v; }, {0.0, 0.5}, {below(0.0), above(0.5), kNaN}},
                   {"floor", [](O& o, double v) { o.floor = v; }, {0.0, 0.5}, {below(0.0), above(0.5), kNaN}},
                   {"averages", [](O& o, double v) { o.averages = static_cast<int>(v); }, {1, 100000}, {0, 100001}},
                   {"calibration", [](O& o, double v) { o.calibration = v; }, {0.0, 0.1}, {below(0.0), above(0.1)}},
                   {"shared_calibration", [](O& o, double v) { o.shared_calibration = v != 0.0; }, {0, 1}, {}}});
  O exact;
  exact.sigma = 0.0;
  EXPECT_THROW(exact.check(), InvalidArgument);  // σ = floor = 0: nothing to predict
}
