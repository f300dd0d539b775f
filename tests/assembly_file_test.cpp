// Tests of the assembly TOML reader (assembly_file module): the example loads, and every kind of
// bad file gives an InputError naming the file, line and key.
#include <gtest/gtest.h>

#include <regex>

#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"

using namespace toolpoint;

namespace {

const std::string kExample = std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml";

std::string example_text() { return read_text_file(kExample); }

std::string replace(std::string s, const std::string& from, const std::string& to) {
  const auto pos = s.find(from);
  EXPECT_NE(pos, std::string::npos) << from;
  if (pos != std::string::npos) s.replace(pos, from.size(), to);
  return s;
}

// Expects an InputError whose message contains every fragment.
void expect_error(const std::string& text, std::initializer_list<const char*> fragments) {
  try {
    parse_assembly(text, "bad.toml");
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string msg = std::string(e.what()) + " | " + e.hint();
    for (const char* f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "'" << f << "' not in: " << msg;
  }
}

}  // namespace

TEST(AssemblyFile, ExampleLoadsWithoutWarnings) {
  const LoadedAssembly la = load_assembly(kExample);
  EXPECT_TRUE(la.warnings.empty());
  // The seed's Table 1 joint is indefinite in stiffness and damping: legal, noted.
  ASSERT_EQ(la.notes.size(), 2u);
  EXPECT_NE(la.notes[0].find("joints.holder_tool"), std::string::npos);
  const Assembly& a = la.assembly;
  EXPECT_EQ(a.spindle.segments.size(), 5u);
  EXPECT_EQ(a.spindle.bearings.size(), 4u);
  EXPECT_EQ(a.holder.size(), 3u);
  EXPECT_DOUBLE_EQ(a.tool.overhang, 0.049);
  EXPECT_DOUBLE_EQ(a.tool.length, 0.123);
  EXPECT_FALSE(a.holder_tool.rigid);
  EXPECT_DOUBLE_EQ(a.holder_tool.parameters.k_yf, 4.19e7);
  EXPECT_DOUBLE_EQ(a.holder_tool.parameters.c_tm, 1.0);
  EXPECT_DOUBLE_EQ(a.spindle_holder.parameters.k_tf, a.spindle_holder.parameters.k_ym);  // defaulted
  EXPECT_DOUBLE_EQ(a.grid.step_hz, 1.0);
}

TEST(AssemblyFile, MissingSectionsAndKeys) {
  const std::string t = example_text();
  expect_error(replace(t, "[tool]\n", "[toolx]\n"), {"bad.toml", "unknown key 'toolx'", "did you mean 'tool'"});
  expect_error(std::regex_replace(t, std::regex("\\[holder\\][^]*?(?=# Tool)"), ""), {"bad.toml", "missing table [holder]"});
  expect_error(replace(t, "overhang = 0.049\n", ""), {"bad.toml:", "missing key tool.overhang", "m"});
  expect_error(replace(t, "youngs_modulus = 5.8e11\n", ""), {"missing key materials.carbide.youngs_modulus", "Pa"});
}

TEST(AssemblyFile, MisspeltKeyGetsASuggestionAndTheLine) {
  const std::string t = replace(example_text(), "length = 0.040\nouter_diameter = 0.032",
                                "lenght = 0.040\nouter_diameter = 0.032");
  expect_error(t, {"bad.toml:", "unknown key 'holder.segment[1].lenght'", "did you mean 'length'"});
  // The line number is the misspelt key's line.
  const std::size_t line = 1 + static_cast<std::size_t>(std::count(t.begin(), t.begin() + t.find("lenght"), '\n'));
  expect_error(t, {("bad.toml:" + std::to_string(line) + ":").c_str()});
}

TEST(AssemblyFile, BearingOutsideSpindle) {
  expect_error(replace(example_text(), "position = 0.395", "position = 0.9"),
               {"bad.toml:", "spindle.bearing[4].position = 0.9 m lies outside the spindle", "from the spindle nose"});
}

TEST(AssemblyFile, NonPositiveDimensions) {
  expect_error(replace(example_text(), "length = 0.070\nouter_diameter = 0.055", "length = -0.070\nouter_diameter = 0.055"),
               {"bad.toml:", "spindle.segment[4]", "length -0.07 m must be > 0"});
  expect_error(replace(example_text(), "outer_diameter = 0.032\ninner_diameter = 0.016",
                       "outer_diameter = 0.032\ninner_diameter = 0.040"),
               {"holder.segment[1]", "inner diameter 0.04 m must be below the outer diameter 0.032 m"});
  expect_error(replace(example_text(), "overhang = 0.049", "overhang = 0"), {"tool.overhang = 0 m must be > 0"});
}

TEST(AssemblyFile, WrongTypesAndSyntax) {
  expect_error(replace(example_text(), "overhang = 0.049", "overhang = \"49 mm\""),
               {"bad.toml:", "tool.overhang must be a number in m", "without quotes"});
  expect_error(replace(example_text(), "overhang = 0.049", "overhang = 0.049 0.05"), {"bad.toml:", "TOML syntax error"});
  expect_error(replace(example_text(), "material = \"carbide\"", "material = \"hss\""),
               {"tool.material = \"hss\" names no material", "carbide, steel"});
  expect_error(replace(example_text(), "[joints.holder_tool]       # the seed's Table 1 (analytical case study)\nk_yf = 4.19e7\n",
                       "[joints.holder_tool]\n"),
               {"missing key joints.holder_tool.k_yf", "N/m"});
}

TEST(AssemblyFile, ModalTermsMustBeAnInteger) {
  for (const char* bad : {"10.7", "0", "1e12"})
    expect_error(replace(example_text(), "modal_terms = 100", std::string("modal_terms = ") + bad),
                 {"bad.toml:", "model.modal_terms", "integer"});
}

TEST(AssemblyFile, ImplausibleMagnitudesWarnWithTheKey) {
  // 80 meant in mm cannot be an 80 m spindle segment: refused at its line (plausibility.hpp's
  // rule: beyond 10× the usual range's top, 2 m).
  const std::string t = replace(example_text(), "length = 0.080\nouter_diameter = 0.045", "length = 80\nouter_diameter = 0.045");
  try {
    parse_assembly(t, "mm.toml");
    ADD_FAILURE() << "an 80 m segment was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mm.toml:78: spindle.segment[5].length = 80"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cannot be meant"), std::string::npos) << e.what();
    EXPECT_NE(e.hint().find("metres"), std::string::npos) << e.hint();
  }
  // 3 m is unusual but could be meant: a warning naming the key, file and line.
  const LoadedAssembly la = parse_assembly(replace(example_text(), "length = 0.080\nouter_diameter = 0.045",
                                                   "length = 3.0\nouter_diameter = 0.045"),
                                           "long.toml");
  ASSERT_EQ(la.warnings.size(), 1u);
  EXPECT_NE(la.warnings[0].find("long.toml:78: spindle.segment[5].length = 3"), std::string::npos) << la.warnings[0];
  EXPECT_NE(la.warnings[0].find("metres"), std::string::npos);
  // Young's modulus in MPa (205000) cannot be meant; 5e8 Pa (a polymer) is only unusual.
  EXPECT_THROW(parse_assembly(replace(example_text(), "youngs_modulus = 2.05e11", "youngs_modulus = 205000"), "mpa.toml"),
               InputError);
  const LoadedAssembly lb = parse_assembly(replace(example_text(), "youngs_modulus = 2.05e11", "youngs_modulus = 5e8"),
                                           "soft.toml");
  ASSERT_EQ(lb.warnings.size(), 1u);
  EXPECT_NE(lb.warnings[0].find("materials.steel.youngs_modulus"), std::string::npos);
}

// The tool's shank must fill the holder's bore where it sits: the section there is composite
// (sleeve and shank bonded), so a 12 mm shank in the example's 16 mm bore — a 4 mm gap the model
// would fill with steel-bonded carbide — is refused, naming the holder segment and the key to
// correct; a shank within 1 % of the bore (fits, interferences: hundredths of a mm) is accepted.
TEST(AssemblyFile, TheShankMustFillTheBore) {
  const std::string shank = "diameter = 0.016\nflute_length";
  expect_error(replace(example_text(), shank, "diameter = 0.016\nshank_diameter = 0.012\nflute_length"),
               {"bad.toml", "holder.segment[1]", "bore of 16 mm", "12 mm", "gap of 4 mm", "tool.shank_diameter",
                "inner_diameter"});
  EXPECT_NO_THROW(
      parse_assembly(replace(example_text(), shank, "diameter = 0.016\nshank_diameter = 0.01599\nflute_length"), "fit.toml"));
}

// Dampings got the stiffnesses' rule (review of issue 13): a joint's c_yf of 5.4e9 N s/m (the
// seed's is 54) and a bearing damping of 5e12 N s/m cannot be meant and are refused at their
// line; and a tool held over nothing (overhang = length, a mistyped overhang) is said.
TEST(AssemblyFile, DampingsAndTheClampedLengthAreJudged) {
  expect_error(replace(example_text(), "c_yf = 54.0", "c_yf = 5.4e9"),
               {"bad.toml:", "c_yf = 5.4e+09", "cannot be meant", "N s/m"});
  const std::string text = example_text();
  const std::size_t bearing = text.find("[[spindle.bearing]]");
  ASSERT_NE(bearing, std::string::npos);
  const std::size_t damping = text.find("damping = ", bearing);
  ASSERT_NE(damping, std::string::npos);
  std::string huge = text;
  huge.replace(damping, text.find('\n', damping) - damping, "damping = 5e12");
  expect_error(huge, {"bad.toml:", "damping = 5e+12", "cannot be meant", "bearing damping"});
  const LoadedAssembly held = parse_assembly(replace(example_text(), "overhang = 0.049", "overhang = 0.123"), "held.toml");
  bool said = false;
  for (const std::string& w : held.warnings) said |= w.find("the tool is held over 0 mm") != std::string::npos;
  EXPECT_TRUE(said);
}
