"""The time-domain simulation against `toolpoint simulate` (the same doubles through the CLI's JSON
and CSV), its arrays' shapes, and the map the same whole, in shards and in the CLI."""
import numpy as np
import pytest

import toolpoint as tp
from conftest import read_csv, run_cli, run_cli_json

BENCH = tp.Mode(0.03993, 0.011, 922.0)  # docs/reference.md §7
CUT = tp.CuttingConditions(2, 6e8, 2e8 / 6e8, immersion=0.05, milling="down")
CLI_CUT = ["--mode-x", "0.03993,0.011,922", "--rigid-y", "--teeth", 2, "--diameter", 20, "--kt", 6e8, "--kn", 2e8,
           "--immersion", 0.05, "--milling", "down", "--feed", 0.1]


def test_one_cut_is_the_cli_one(tmp_path):
    r = tp.simulate_milling(CUT, 10000.0, 2e-3, 1e-4, 0.02, x_modes=[BENCH], rigid_y=True, revolutions=20)
    cli = run_cli_json("simulate", *CLI_CUT, "--rpm", 10000, "--depth", 2, "--revolutions", 20,
                       "--output", tmp_path / "sim")
    assert r.to_dict()["simulation"] == cli["simulation"]
    assert r.stable and r.steps_per_tooth == 111
    h = r.history
    steps = 20 * 2 * 111
    assert h["time_s"].shape == (steps + 1,) and h["tooth_1_force_n"].shape == (steps + 1,)
    csv = read_csv(tmp_path / "sim" / "history.csv")
    assert np.array_equal(csv[:, 1], h["force_x_n"]) and np.array_equal(csv[:, 3], h["x_m"])
    assert r.per_tooth["time_s"].shape == (40,) and r.per_revolution["x_m"].shape == (21,)
    assert r.walls[0]["angle_rad"] == pytest.approx(np.pi)


def test_map_whole_in_shards_and_in_the_cli(tmp_path):
    kw = dict(x_modes=[BENCH], rigid_y=True, revolutions=20)
    whole = tp.simulated_map(CUT, (8000.0, 20000.0, 5), (0.5e-3, 6e-3, 6), 1e-4, 0.02, threads=2, **kw)
    parts = [tp.simulated_map(CUT, (8000.0, 20000.0, 5), (0.5e-3, 6e-3, 6), 1e-4, 0.02, shard=(i, 2), **kw) for i in (1, 0)]
    merged = tp.merge_simulated_map_parts(parts, ["p1", "p0"])
    for key, col in whole.table.items():
        assert np.array_equal(col, merged.table[key], equal_nan=True), key
    run_cli("simulate", "map", *CLI_CUT, "--rpm", "8000:20000", "--speeds", 5, "--depth", "0.5:6", "--depths", 6,
            "--revolutions", 20, "--output", tmp_path / "map")
    csv = read_csv(tmp_path / "map" / "map.csv")
    assert np.array_equal(csv[:, 2], whole.table["stable"])
    assert np.array_equal(csv[:, 0], whole.table["spindle_speed_rpm"])
    assert whole.to_dict()["cells"] == 30
    # The lowest unstable depth rises with the lobes: finite where the map reaches chatter.
    assert np.all(whole.boundary["depth_m"] > 0.0)


def test_bad_input_is_refused_naming_the_field():
    with pytest.raises(tp.InvalidArgument, match="Cutter::runout_m"):
        tp.simulate_milling(CUT, 10000.0, 1e-3, 1e-4, 0.02, x_modes=[BENCH], rigid_y=True, runout_m=[0.0, 0.02])
    with pytest.raises(tp.InvalidArgument, match="Cutter::pitch_rad"):
        tp.simulate_milling(CUT, 10000.0, 1e-3, 1e-4, 0.02, x_modes=[BENCH], rigid_y=True, pitch_rad=[2.0, 2.0])
    with pytest.raises(tp.InvalidArgument, match="SimulationOptions::steps_per_tooth"):
        tp.simulate_milling(CUT, 2000.0, 1e-3, 1e-4, 0.02, x_modes=[BENCH], rigid_y=True, steps_per_tooth=4)
