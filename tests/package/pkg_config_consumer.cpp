// A consumer built with `pkg-config --cflags --libs toolpoint` only (tests/package/consumer_test.cmake):
// it reads the assembly file (toml++) and evaluates the tool point FRF through the SIMD sweep
// (SLEEF), so every library the static libtoolpoint needs must be on the link line.
#include <cstdio>

#include <toolpoint/io/assembly_file.hpp>
#include <toolpoint/error.hpp>
#include <toolpoint/version.hpp>

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  try {
    const toolpoint::AssemblyModel model(toolpoint::load_assembly(argv[1]).assembly);
    const toolpoint::BlockSeries sht = model.tool_point(std::vector<double>{2580.0, 2585.0, 2590.0, 2595.0});
    std::printf("toolpoint %s: tool point |H| at 2585 Hz: %.4e m/N\n", toolpoint::version, std::abs(sht.blocks[1](0, 0)));
    return 0;
  } catch (const toolpoint::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
