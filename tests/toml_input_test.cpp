// The TOML guard before toml++ (src/toml_input.hpp). Debian's toml++ 3.3.0 reaches
// __builtin_unreachable on a non-ASCII character where whitespace may stand, and fails internal
// assertions (assumptions in a release build) on `[%`, `y=1979-05-27T:` and `[[t]]\nl=[}` — the
// fuzz findings of issue 12. Each must be refused by the guard itself, with line and column,
// before toml++ sees it. The other half: the guard must never refuse valid TOML. Its oracle is
// toml++ (every valid snippet below parses there) and the TOML 1.0 specification's own examples.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "../src/toml_input.hpp"
#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/io/joint_file.hpp"

using namespace toolpoint;

namespace {

// The guard's message for `text`, or "" when it lets the text through.
std::string guard_message(const std::string& text) {
  try {
    check_toml_text(text, "t.toml", "hint");
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

// A code point as UTF-8.
std::string utf8(char32_t c) {
  std::string s;
  if (c < 0x80) {
    s += static_cast<char>(c);
  } else if (c < 0x800) {
    s += static_cast<char>(0xC0 | (c >> 6));
    s += static_cast<char>(0x80 | (c & 0x3F));
  } else {
    s += static_cast<char>(0xE0 | (c >> 12));
    s += static_cast<char>(0x80 | ((c >> 6) & 0x3F));
    s += static_cast<char>(0x80 | (c & 0x3F));
  }
  return s;
}

}  // namespace

TEST(TomlGuard, FuzzFindingsAreRefusedWithLineAndColumn) {
  // The three assertion inputs: each refused where the fault is.
  EXPECT_NE(guard_message("[%").find("t.toml:1:2: TOML syntax error: expected a key"), std::string::npos) << guard_message("[%");
  EXPECT_NE(guard_message("y=1979-05-27T:").find("t.toml:1:14:"), std::string::npos) << guard_message("y=1979-05-27T:");
  EXPECT_NE(guard_message("y=1979-05-27T:").find("needs the time"), std::string::npos);
  EXPECT_NE(guard_message("[[t]]\nl=[}").find("t.toml:2:4: TOML syntax error: expected a value"), std::string::npos)
      << guard_message("[[t]]\nl=[}");
  // Their relatives: a value terminator where a value must start, a key that is no key.
  for (const char* bad : {"a=[1,}", "a=[\n#c\n}]", "a.%=1", "a={%=1}", "a=_1", "a=[1,,2]", "[a.]", "a=.5"})
    EXPECT_NE(guard_message(bad).find("TOML syntax error"), std::string::npos) << bad;
  // The unreachable: one non-ASCII character where whitespace may stand, from each range the
  // fuzzer found (U+00A1–U+0499, U+2C5E–U+3057, U+FB26–U+FEFE) and the example.
  for (char32_t c : {0xA1, 0xB5, 0x499, 0x2C5E, 0x3057, 0xFB26, 0xFEFE}) {
    for (const std::string& text : {"a = 1 " + utf8(c) + "\n", "a" + utf8(c) + "= 1\n", "[t" + utf8(c) + "]\n",
                                    "a = [1," + utf8(c) + "2]\n", "a = 1\n" + utf8(c) + "b = 2\n"}) {
      const std::string m = guard_message(text);
      EXPECT_NE(m.find("outside a string or comment"), std::string::npos) << text << " → " << m;
    }
  }
  // Found by the in-tree fuzzer (fuzz/fuzz_assembly_toml.cpp): toml++ tests what follows a
  // backslash in a string with the same whitespace function.
  EXPECT_NE(guard_message("a = \"x\\µ\"").find("1:7: TOML syntax error: '\\' followed by 'µ' (U+00B5) is not an escape"),
            std::string::npos)
      << guard_message("a = \"x\\µ\"");
  EXPECT_NE(guard_message("a = \"\"\"x\\ \t µ\"\"\"").find("not an escape sequence"), std::string::npos);
  EXPECT_NE(guard_message("a = \"\"\"x\\  \n\n   µm\"\"\"")
                .find("3:4: TOML syntax error: 'µ' (U+00B5) right after a "
                      "line-ending backslash"),
            std::string::npos)
      << guard_message("a = \"\"\"x\\  \n\n   µm\"\"\"");
  // A date, a space and one digit: toml++ reads on past the digit unchecked.
  EXPECT_NE(guard_message("y=1979-05-27 7 # c").find("1:15: TOML syntax error: a date-time needs the time"), std::string::npos)
      << guard_message("y=1979-05-27 7 # c");
  const std::string m = guard_message("[tool]\noverhang = 49 µm\n");
  EXPECT_NE(m.find("t.toml:2:15: TOML syntax error: expected the end of the line"), std::string::npos) << m;
  EXPECT_NE(m.find("'µ' (U+00B5) outside a string or comment"), std::string::npos) << m;
}

TEST(TomlGuard, RefusesWhatTomlForbidsAnywhere) {
  EXPECT_NE(guard_message("a = \"x\xC3\x28\"").find("1:7: TOML syntax error: byte 0xC3 is not valid UTF-8"), std::string::npos);
  EXPECT_NE(guard_message("a = 1\nb = \"\x01\"").find("2:6: TOML syntax error: control character U+0001"), std::string::npos);
  EXPECT_NE(guard_message("a = 1\rb = 2").find("control character U+000D"), std::string::npos);
  EXPECT_NE(guard_message("a = \"open\nb = 1").find("1:5: TOML syntax error: a \"string\" not closed"), std::string::npos);
  EXPECT_NE(guard_message("a = '''x\n\n").find("1:5: TOML syntax error: a multi-line string"), std::string::npos);
  EXPECT_NE(guard_message("a = {b = 1,\nc = 2}").find("TOML syntax error"), std::string::npos);
  EXPECT_NE(guard_message("a = 1 2").find("expected the end of the line"), std::string::npos);
  EXPECT_NE(guard_message("a =").find("expected a value, saw the end of the file"), std::string::npos);
  std::string deep = "a = " + std::string(150, '[') + std::string(150, ']');
  EXPECT_NE(guard_message(deep).find("nested deeper than"), std::string::npos);
}

TEST(TomlGuard, LetsValidTomlThrough) {
  // Valid TOML 1.0 (mostly the specification's examples); toml++ parses every one.
  const std::vector<std::string> valid = {
      "",
      "\xEF\xBB\xBF"
      "a = 1\n",
      "# only a comment: µm, °, – and tabs\t\n",
      "a = 1\r\nb = 2\r\n",
      "key = \"value\"\nbare_key = \"value\"\nbare-key = \"value\"\n1234 = \"value\"\n",
      "\"127.0.0.1\" = \"value\"\n\"character encoding\" = \"value\"\n\"ʎǝʞ\" = \"value\"\n'key2' = \"value\"\n'quoted "
      "\"value\"' = \"value\"\n",
      "name = \"Orange\"\nphysical.color = \"orange\"\nsite.\"google.com\" = true\n fruit . flavor = \"banana\"\n",
      "str = \"I'm a string. \\\"You can quote me\\\". Name\\tJos\\u00E9\\nLocation\\tSF.\"\n",
      "str1 = \"\"\"\nRoses are red\nViolets are blue\"\"\"\n",
      "str3 = \"\"\"\\\n       The quick brown \\\n       fox jumps over \\\n       the lazy dog.\\\n       \"\"\"\n",
      "str4 = \"\"\"Here are two quotation marks: \"\". Simple enough.\"\"\"\n",
      "str5 = \"\"\"Here are three quotation marks: \"\"\\\".\"\"\"\n",
      "str7 = \"\"\"\"This,\" she said, \"is just a pointless statement.\"\"\"\"\n",
      "winpath = 'C:\\Users\\nodejs\\templates'\nregex = '<\\i\\c*\\s*>'\n",
      "lines = '''\nThe first newline is\ntrimmed in raw strings.\n'''\nquot15 = '''Here are fifteen quotation marks: "
      "\"\"\"\"\"\"\"\"\"\"\"\"\"\"\"'''\n"
      "apos15 = \"Here are fifteen apostrophes: '''''''''''''''\"\nstr = ''''That,' she said, 'is still pointless.''''\n",
      "int1 = +99\nint2 = 42\nint3 = 0\nint4 = -17\nint5 = 1_000\nhex1 = 0xDEADBEEF\noct1 = 0o755\nbin1 = 0b11010110\n",
      "flt1 = +1.0\nflt2 = 3.1415\nflt3 = -0.01\nflt4 = 5e+22\nflt5 = 1e06\nflt6 = -2E-2\nflt7 = 6.626e-34\n"
      "flt8 = 224_617.445_991_228\nsf1 = inf\nsf2 = +inf\nsf3 = -inf\nsf4 = nan\nsf5 = +nan\nsf6 = -nan\n",
      "bool1 = true\nbool2 = false\n",
      "odt1 = 1979-05-27T07:32:00Z\nodt2 = 1979-05-27T00:32:00-07:00\nodt3 = 1979-05-27T00:32:00.999999-07:00\n"
      "odt4 = 1979-05-27 07:32:00Z\nldt1 = 1979-05-27T07:32:00\nld1 = 1979-05-27\nlt1 = 07:32:00\nlt2 = 00:32:00.999999\n",
      "integers = [ 1, 2, 3 ]\ncolors = [ \"red\", \"yellow\", \"green\" ]\nnested_arrays_of_ints = [ [ 1, 2 ], [3, 4, 5] ]\n"
      "nested_mixed_array = [ [ 1, 2 ], [\"a\", \"b\", \"c\"] ]\nstring_array = [ \"all\", 'strings', \"\"\"are the same\"\"\", "
      "'''type''' ]\n"
      "numbers = [ 0.1, 0.2, 0.5, 1, 2, 5 ]\ncontributors = [\n  \"Foo Bar <foo@example.com>\",\n  { name = \"Baz Qux\", email = "
      "\"bazqux@example.com\", url = \"https://example.com/bazqux\" }\n]\n",
      "integers2 = [\n  1, 2, 3\n]\nintegers3 = [\n  1,\n  2, # this is ok\n]\nempty = []\nempty2 = [ # c\n]\n",
      "[table-1]\nkey1 = \"some string\"\nkey2 = 123\n\n[table-2]\nkey1 = \"another string\"\nkey2 = 456\n",
      "[dog.\"tater.man\"]\ntype.name = \"pug\"\n[a.b.c]\n[ d.e.f ]\n[ g .  h  . i ]\n[ j . \"ʞ\" . 'l' ]\n",
      "name = { first = \"Tom\", last = \"Preston-Werner\" }\npoint = { x = 1, y = 2 }\nanimal = { type.name = \"pug\" }\nempty "
      "= {}\n",
      "[[products]]\nname = \"Hammer\"\nsku = 738594937\n\n[[products]]  # empty table within the array\n\n[[ products ]]\n"
      "name = \"Nail\"\n",
      "[[fruits]]\nname = \"apple\"\n[fruits.physical]  # subtable\ncolor = \"red\"\n[[fruits.varieties]]  # nested array of "
      "tables\n"
      "name = \"red delicious\"\n",
      "a = \"µm in a string, ° and – too\" # and µ in a comment\n",
      "points = [ { x = 1, y = 2, z = 3 },\n           { x = 7, y = 8, z = 9 } ]\n",
  };
  for (const std::string& text : valid) {
    EXPECT_EQ(guard_message(text), "") << text;
    EXPECT_NO_THROW(parse_toml(text, "t.toml", "hint")) << text;
  }
  // The example assembly file, comments and all.
  const std::string example = read_text_file(std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml");
  EXPECT_EQ(guard_message(example), "");
}

TEST(TomlGuard, TomlppErrorsBecomeInputErrorsWithLineAndColumn) {
  // Lexically fine, semantically not: toml++'s own error, converted.
  try {
    parse_toml("a = 1\na = 2\n", "dup.toml", "see the example");
    FAIL() << "a duplicate key was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("dup.toml:2:"), std::string::npos) << e.what();
    EXPECT_EQ(e.hint(), "see the example");
  }
  // Through the joint file loader: the same guard.
  try {
    parse_joint_file("[joint]\ninterface = \"holder_tool\"\nk_yf = 4.19e7 N/µm\n", "kht.toml");
    FAIL() << "a unit after a number was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("kht.toml:3:15: TOML syntax error: expected the end of the line"), std::string::npos)
        << e.what();
  }
  const JointFile seed = load_joint_file(std::string(TOOLPOINT_SOURCE_DIR) + "/fuzz/seeds/holder_tool_joint.toml");
  EXPECT_EQ(seed.parameters.k_yf, 4.19e7);
  // Through the assembly loader, as a user meets it.
  try {
    parse_assembly("[tool]\noverhang = 49 µm\n", "mm.toml");
    FAIL() << "49 µm was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("mm.toml:2:15: TOML syntax error"), std::string::npos) << e.what();
    EXPECT_NE(e.hint().find("4.9e-5"), std::string::npos) << e.hint();
  }
}
