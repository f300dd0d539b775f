// libFuzzer target: the assembly TOML loader (the TOML guard, toml++ compiled in with its
// assertions on, and the assembly reader). Any input may be refused with InputError; nothing else
// may leave parse_assembly, and no sanitizer or toml++ assertion may fire.
#include <cstddef>
#include <cstdint>
#include <string>

#include "toolpoint/assembly_file.hpp"
#include "toolpoint/error.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    toolpoint::parse_assembly(text, "fuzz.toml");
  } catch (const toolpoint::InputError&) {
  }
  return 0;
}
