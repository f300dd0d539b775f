// Identify the holder–tool joint from two measured FRF files by the seed's procedure (closed form,
// seed Eq. 6, read where the joint controls a mode) — `toolpoint identify --method seed`, as one
// library call in a program of your own.
//
//   identify_joint ASSEMBLY.toml SH11.csv SHT11.csv
//
// SH11 (holder tip, tool outside removed) and SHT11 (tool point) are 2×2 block FRF CSV files on
// one grid (frequency_hz, then re/im of H, L, N, P in SI units), e.g. from a tap test and
// `toolpoint rotational`, or from `toolpoint predict`. The assembly file gives the model's tool
// (its free–free receptances T enter Eq. 6) and the trial joint: effect analysis on the model
// names the mode the joint controls, and the parameters are the medians over ±2 % around the
// measured peak nearest it (the rule `toolpoint identify` and `toolpoint demo` use). The forward
// check and the verdict come with it.
#include <cstdio>

#include <toolpoint/io/assembly_file.hpp>
#include <toolpoint/error.hpp>
#include <toolpoint/io/io.hpp>
#include <toolpoint/studies/identification.hpp>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s ASSEMBLY.toml SH11.csv SHT11.csv\n", argv[0]);
    return 2;
  }
  try {
    const toolpoint::Assembly assembly = toolpoint::load_assembly(argv[1]).assembly;
    toolpoint::IdentificationData data;
    data.G11 = toolpoint::read_block_csv(argv[3]);
    data.g_name = argv[3];
    data.B11 = toolpoint::read_block_csv(argv[2]);
    data.b_name = argv[2];
    toolpoint::IdentificationOptions options;
    options.route = toolpoint::Route::HolderTool;
    options.method = toolpoint::IdentificationMethod::Seed;
    const toolpoint::Identification id = toolpoint::run_identification_study(assembly, {data}, options);

    const toolpoint::JointReadout& r = id.seed;
    std::printf("holder-tool joint read at %.1f Hz, %s (%zu points, %.1f to %.1f Hz)\n", id.mode.center_hz,
                id.mode.method.c_str(), r.points, r.band_lo_hz, r.band_hi_hz);
    for (int i = 0; i < 8; ++i)
      std::printf("%-5s %12.6g %-10s (noise gain %.3g)\n", toolpoint::JointParameters::name(i), id.identified[i],
                  toolpoint::JointParameters::unit(i), r.noise_gain[i]);
    std::printf("verdict: %s\n", toolpoint::to_string(id.verdict.verdict));
    for (const std::string& why : id.verdict.reasons) std::printf("  %s\n", why.c_str());
    for (const std::string& w : id.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    return 0;
  } catch (const toolpoint::Error& e) {
    std::fprintf(stderr, "error: %s\n  fix: %s\n", e.what(), e.hint().c_str());
    return 1;
  }
}
