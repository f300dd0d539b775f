// From an assembly file to chatter stability lobes, in a program of your own:
// assembly → tool point FRF SHT11 (the prediction study: receptance coupling, seed Eq. 1–5) → zero-order lobes
// (Altintas & Budak 1995) → the absolute stability limit and the best spindle speeds.
//
//   tool_point_to_lobes ASSEMBLY.toml
//
// The cut is illustrative: a 2-flute end mill, 50 % radial immersion, down-milling, aluminium-like
// cutting coefficients K_t = 6e8 N/m², K_n = 2e8 N/m² (K_r = 1/3); speeds 5000–25000 rpm. The tool
// is taken as symmetric (G_yy = G_xx, no cross terms).
#include <cstdio>

#include <toolpoint/io/assembly_file.hpp>
#include <toolpoint/error.hpp>
#include <toolpoint/stability/stability.hpp>
#include <toolpoint/studies/predict.hpp>
#include <toolpoint/version.hpp>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s ASSEMBLY.toml\n", argv[0]);
    return 2;
  }
  try {
    const toolpoint::LoadedAssembly loaded = toolpoint::load_assembly(argv[1]);
    for (const std::string& w : loaded.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());

    // SHT11 on the file's [analysis] grid, with its modes; its H entry (w/f, m/N) is G_xx.
    const toolpoint::Prediction sht = toolpoint::run_prediction_study(loaded.assembly);
    for (const std::string& w : sht.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    toolpoint::MillingFrfs frfs;
    frfs.xx = toolpoint::entry(sht.frf, 0);

    toolpoint::CuttingConditions cut;
    cut.teeth = 2;
    cut.tangential_coefficient = 6e8;
    cut.radial_ratio = 2e8 / 6e8;
    cut.engagement = toolpoint::engagement_from_immersion(0.5, toolpoint::MillingDirection::Down);
    toolpoint::ZeroOrderOptions options;
    options.speeds = {5000.0, 25000.0, 2000};
    const toolpoint::ZeroOrderResult lobes = toolpoint::zero_order_lobes(frfs, cut, options);

    std::printf("toolpoint %s: %s, %zu frequencies\n", toolpoint::version, loaded.assembly.name.c_str(), sht.frf.size());
    std::printf("tool point modes (peaks of |H|):");
    for (const toolpoint::Peak& m : sht.modes) std::printf(" %.0f Hz", m.frequency_hz);
    std::printf("\n");
    std::printf("absolute stability limit %.3f mm (chatter at %.0f Hz), %d lobes\n", 1e3 * lobes.floor_depth_m,
                lobes.floor_chatter_hz, lobes.lobes + 1);
    std::printf("best speeds (stability pockets):\n");
    for (const toolpoint::EnvelopePoint& p : toolpoint::stability_pockets(lobes.envelope, 3))
      std::printf("  %8.0f rpm  %.3f mm\n", p.speed_rpm, 1e3 * p.depth_m);
    for (const std::string& w : lobes.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    return 0;
  } catch (const toolpoint::Error& e) {
    std::fprintf(stderr, "error: %s\n  fix: %s\n", e.what(), e.hint().c_str());
    return 1;
  }
}
