// libFuzzer target: the TOML files toolpoint reads — the assembly file and the joint file — through
// the TOML guard (src/toml_input.hpp), toml++ (compiled in, with its assertions on) and the
// loaders. Any input may be refused with InputError; nothing else may leave them, and no
// sanitizer or toml++ assertion may fire.
#include <cstddef>
#include <cstdint>
#include <string>

#include "toolpoint/io/assembly_file.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/joint_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    toolpoint::parse_assembly(text, "fuzz.toml");
  } catch (const toolpoint::InputError&) {}
  try {
    toolpoint::parse_joint_file(text, "fuzz_joint.toml");
  } catch (const toolpoint::InputError&) {}
  return 0;
}
