// Identify the holder–tool joint from two measured FRF files, with the library's closed form
// (seed Eq. 6) — the core of `toolpoint identify`, in a program of your own.
//
//   identify_joint ASSEMBLY.toml SH11.csv SHT11.csv
//
// SH11 (holder tip, tool outside removed) and SHT11 (tool point) are 2×2 block FRF CSV files on
// one grid (frequency_hz, then re/im of H, L, N, P in SI units), e.g. from a tap test and
// `toolpoint rotational`, or from `toolpoint predict`. The assembly file gives the model's tool
// (its free–free receptances T enter Eq. 6). K(ω) is read where the joint controls a mode: effect
// analysis on the model names that mode, and the parameters are the medians over ±2 % around it.
#include <cstdio>

#include <toolpoint/assembly_file.hpp>
#include <toolpoint/error.hpp>
#include <toolpoint/identify.hpp>
#include <toolpoint/io.hpp>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s ASSEMBLY.toml SH11.csv SHT11.csv\n", argv[0]);
    return 2;
  }
  try {
    const toolpoint::Assembly assembly = toolpoint::load_assembly(argv[1]).assembly;
    const toolpoint::BlockSeries sh = toolpoint::read_block_csv(argv[2]);
    const toolpoint::BlockSeries sht = toolpoint::read_block_csv(argv[3]);
    const toolpoint::AssemblyModel model(assembly);

    // K_ht(ω) at every frequency: A = T (the model's tool), B11 = SH11, G11 = SHT11.
    const toolpoint::JointSeries k = toolpoint::identify_series([&](double f) { return model.tool(f); }, sh, argv[2], sht,
                                                                argv[3]);

    // The mode the holder–tool joint controls, and the band around it.
    const toolpoint::EffectAnalysis effect = toolpoint::effect_analysis(assembly, toolpoint::Route::HolderTool, sht.frequency_hz);
    const double mode_hz = effect.modes[effect.dominant].frequency_hz;
    const toolpoint::JointReadout r = toolpoint::band_readout(k, 0.98 * mode_hz, 1.02 * mode_hz);

    std::printf("holder-tool joint read at %.1f Hz (%zu points, %.1f to %.1f Hz)\n", mode_hz, r.points, r.band_lo_hz,
                r.band_hi_hz);
    for (int i = 0; i < 8; ++i)
      std::printf("%-5s %12.6g %-10s (noise gain %.3g)\n", toolpoint::JointParameters::name(i), r.parameters[i].median,
                  toolpoint::JointParameters::unit(i), r.noise_gain[i]);
    for (const std::string& w : r.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    return 0;
  } catch (const toolpoint::Error& e) {
    std::fprintf(stderr, "error: %s\n  fix: %s\n", e.what(), e.hint().c_str());
    return 1;
  }
}
