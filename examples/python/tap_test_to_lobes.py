#!/usr/bin/env python3
"""The tutorial (docs/tutorial.md) through the Python API: from a (virtual) tap test to an identified joint,
the tool point FRF at other overhangs, and stability lobes.

    PYTHONPATH=build/python python3 examples/python/tap_test_to_lobes.py [--bootstrap 200]

Each step names the CLI command it stands for. Figures are drawn with matplotlib when it is
installed (skipped with a note otherwise).
"""
import argparse
import sys
from pathlib import Path

import numpy as np

import toolpoint as tp

EXAMPLE = Path(__file__).resolve().parents[1] / "bt40_shrinkfit_16mm.toml"


def run(args):
    # 1. The assembly, checked with a prediction (toolpoint predict).
    assembly = tp.load_assembly(args.assembly).assembly
    prediction = tp.run_prediction_study(assembly)
    f = prediction.frequency_hz
    print("1. model modes [Hz]:", ", ".join(f"{m.frequency_hz:.1f}" for m in prediction.modes))

    # 2. Tap tests with the hammer at every point, 0.5 % noise (toolpoint taptest --at holder/tool).
    holder = tp.run_tap_test_study(assembly, spacing_m=0.02, side="holder", sigma=0.005)
    tool = tp.run_tap_test_study(assembly, spacing_m=0.015, side="tool", sigma=0.005, seed=11)
    print(f"2. tap tests: {len(holder.frfs)} FRFs on the holder, {len(tool.frfs)} on the tool; "
          f"κGA under the points {holder.shear_stiffness_n:.4g} N and {tool.shear_stiffness_n:.4g} N")

    # 3. Rotational FRFs by second-order finite differences, shear strain removed, and the
    # differences' truncation error estimated on the model and removed
    # (toolpoint rotational --model A.toml --at holder/tool).
    def block(test, spacing, side):
        H = {(r.response, r.hammer): r.values for r in test.frfs}
        differences = tp.RotationalOptions(spacing=spacing, order=2, shear_stiffness=test.shear_stiffness_n)
        measured = tp.rotational_frfs(f, H, differences).block
        e = tp.finite_difference_error(assembly, f, list(H), differences, side=side)
        return measured - e.error

    sh11, sht11 = block(holder, 0.02, "holder"), block(tool, 0.015, "tool")

    # 4. The holder–tool joint (Eq. 6) from the raw data: the band fit with intervals, the seed's
    # read-out beside it (toolpoint identify).
    ident = tp.run_identification_study(assembly, [tp.IdentificationData(f, sht11, B11=sh11)],
                                        bootstrap_samples=args.bootstrap, threads=args.threads)
    print(f"4. holder–tool joint ({ident.equation}), verdict {ident.verdict}" +
          "".join(f"\n   - {r}" for r in ident.verdict_reasons) + ":")
    ref = assembly.holder_tool
    for k, (name, unit) in enumerate(zip(tp.JointParameters.names(), tp.JointParameters.units())):
        fit = ident.fit
        print(f"   {name:<5} {fit.estimate[k]:>11.5g} {unit:<10} 95 % [{fit.lower[k]:.5g}, {fit.upper[k]:.5g}]"
              f"  (the file's {ref[k]:.4g}; seed read-out {ident.seed.median[k]:.4g})")
    joint = ident.joint_file()

    # 5. The tool point FRF for other overhangs with the identified joint, from the measured SH11
    # filtered by Savitzky–Golay, window 41, order 2 (toolpoint filter; toolpoint couple --joint).
    sh11_f = tp.savgol_filter(sh11, 41, 2, frequency_hz=f)
    identified = assembly.with_joint(joint)
    overhangs = [0.040 + i * 0.004 for i in range(6)]
    study = tp.run_overhang_study(identified, f, sh11_f, overhangs_m=overhangs, threads=args.threads)
    print("5. tracked modes [Hz] per overhang [mm]:")
    for o, column in zip(overhangs, study.tracked_modes_hz.T):
        print(f"   {1e3 * o:5.1f} mm: " + ", ".join(f"{x:.1f}" for x in column))

    # 6. Stability lobes at 48 mm: 4 flutes, half immersion, down-milling (toolpoint lobes).
    H48 = study.overhangs[2].sht11[:, 0, 0]
    cutting = tp.CuttingConditions(4, 6e8, 0.3, immersion=0.5, milling="down")
    lobes = tp.run_lobes_study(cutting, (2000.0, 20000.0, 0), frequency_hz=f, xx=H48)
    z = lobes.zero_order
    print(f"6. absolute stability limit {1e3 * z.floor_depth_m:.4f} mm (chatter at {z.floor_chatter_hz:.1f} Hz); best speeds:")
    p = lobes.pockets
    for n, a, fc, k in zip(p["speed_rpm"], p["depth_m"], p["chatter_hz"], p["lobe"]):
        print(f"   {n:7.0f} rpm  {1e3 * a:7.4f} mm  (chatter {fc:.1f} Hz, lobe {k})")
    draw(f, sht11, study, lobes, Path(args.figures))
    return {"sh11": sh11, "sh11_f": sh11_f, "sht11": sht11, "identification": ident, "study": study, "lobes": lobes}


def draw(f, sht11, study, lobes, folder):
    try:
        import matplotlib
    except ImportError:
        print("matplotlib is not installed: figures skipped (apt-get install python3-matplotlib to draw them)", file=sys.stderr)
        return
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    folder.mkdir(parents=True, exist_ok=True)
    fig, ax = plt.subplots()
    for r in study.overhangs:
        ax.semilogy(f, np.abs(r.sht11[:, 0, 0]), lw=0.8, label=f"{1e3 * r.overhang_m:.0f} mm")
    ax.set(xlabel="frequency [Hz]", ylabel="|H| [m/N]", title="Tool point FRF per overhang")
    ax.legend()
    fig.savefig(folder / "overhangs.png", dpi=120)
    fig, ax = plt.subplots()
    e = lobes.envelope
    ax.plot(e["speed_rpm"], 1e3 * e["depth_m"])
    ax.set(xlabel="spindle speed [rpm]", ylabel="axial depth [mm]", title="Stable envelope (zero-order)", ylim=(0, None))
    fig.savefig(folder / "lobes.png", dpi=120)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--assembly", default=str(EXAMPLE), help="assembly file (TOML, SI units)")
    ap.add_argument("--bootstrap", type=int, default=200, help="bootstrap replicates of the joint's intervals (≥ 20)")
    ap.add_argument("--threads", type=int, default=0, help="worker threads (0: every core; the same results for any number)")
    ap.add_argument("--figures", default="toolpoint-tutorial-py", help="folder for the matplotlib figures")
    return run(ap.parse_args(argv))


if __name__ == "__main__":
    main()
