#!/usr/bin/python3
"""The numbers and output the documentation quotes, checked against the tool (Docs.QuotedOutputMatches).

    check_quoted_output.py SOURCE_DIR TOOLPOINT

Three kinds of checks, in a scratch folder that has build/toolpoint and examples/ as a checkout has:
  1. Quoted output. A code block right after a line `<!-- output of: COMMAND -->` in README.md or
     docs/*.md quotes COMMAND's output: COMMAND is run and every non-blank line of the block must
     be a line of its standard output, character for character (a block may leave lines out).
  2. Numbers in the text. CLAIMS below lists phrases of docs/tutorial.md's demo section with the
     number they quote in braces, and what the demo computed for it (its summary.json). The phrase
     must be in the document (whitespace and line breaks aside) and the number must agree to the
     digits quoted: "equal" is within half a unit of the last quoted digit; "bound" (a "within X")
     holds when the value is at most X plus that half unit. A claim with no number is a yes/no fact.
  3. The README's tour: its ```sh block runs as written (sh -e) and exits 0.
What is not covered: figures measured elsewhere and quoted as such (Performance, the coverage
tables of long Monte Carlo runs, docs/cluster.md's timings), and the prose of the other pages;
the tutorial's own promises are checked by Tutorial.RunsAsWrittenInTheDocs, the Python page's
example by python/tests/test_examples.py.
"""
import cmath
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path


def demo(s):
    return s["demo/summary.json"]


def fitted_errors(d, prefix):
    ref, par = d["reference"], d["fitted"]["parameters"]
    return max(abs(par[k]["estimate"] / ref[k] - 1.0) * 100 for k in ref if k.startswith(prefix))


def damping_share(d):
    # ωc/|K| of K_yf = k_yf + iωc_yf at the tool mode (the reference joint: Table 1).
    ref, eff = d["reference"], d["effect"]
    w = 2 * math.pi * eff["modes"][eff["dominant"]]["frequency_hz"]
    return 100 * w * ref["c_yf"] / abs(complex(ref["k_yf"], w * ref["c_yf"]))


# (document, phrase with the quoted number in braces, "equal" | "bound" | "fact", value from the results)
CLAIMS = [
    ("docs/tutorial.md", "SH11 and SHT11 at {4991} frequencies, 10–5000 Hz", "equal", lambda s: demo(s)["points"]),
    ("docs/tutorial.md", "10–5000 Hz", "fact", lambda s: demo(s)["frequency_range_hz"] == [10.0, 5000.0]),
    ("docs/tutorial.md", "within {1.2e-8} at every frequency", "bound", lambda s: max(demo(s)["clean_max_deviation"].values())),
    ("docs/tutorial.md", "{5} % multiplicative noise", "equal", lambda s: 100 * demo(s)["noise"]["sigma"]),
    ("docs/tutorial.md", "the tool mode at {2585} Hz", "equal",
     lambda s: demo(s)["effect"]["modes"][demo(s)["effect"]["dominant"]]["frequency_hz"]),
    ("docs/tutorial.md", "filtered with an {81}-point window", "equal", lambda s: demo(s)["filter"]["window_points"]),
    ("docs/tutorial.md", "it is {2} % of |K_yf| at the tool mode", "equal", lambda s: damping_share(demo(s))),
    ("docs/tutorial.md", "its noise gain is {272}", "equal",
     lambda s: demo(s)["filtered_readout"]["parameters"]["c_yf"]["noise_gain"]),
    ("docs/tutorial.md", "(its verdict is *doubtful*)", "fact", lambda s: demo(s)["seed"]["verdict"]["verdict"] == "doubtful"),
    ("docs/tutorial.md", "every stiffness within {0.05} %", "bound", lambda s: fitted_errors(demo(s), "k_")),
    ("docs/tutorial.md", "every damping within {1.3} %", "bound", lambda s: fitted_errors(demo(s), "c_")),
    ("docs/tutorial.md", "each inside its 95 % interval", "fact",
     lambda s: all(p["lower"] <= demo(s)["reference"][k] <= p["upper"] for k, p in demo(s)["fitted"]["parameters"].items())),
    ("docs/tutorial.md", "within {0.001} % in frequency", "bound",
     lambda s: 100 * max(abs(m["frequency_error"]) for m in demo(s)["fit_verification"])),
    ("docs/tutorial.md", "and {0.06} % in peak height", "bound",
     lambda s: 100 * max(abs(m["magnitude_error"]) for m in demo(s)["fit_verification"])),
]


def half_unit(text):
    m = re.fullmatch(r"\d+(?:\.(\d+))?(?:e([-+]?\d+))?", text)
    return 0.5 * 10.0 ** (int(m.group(2) or 0) - len(m.group(1) or ""))


def flat(text):
    return re.sub(r"\s+", " ", text)


def main():
    source, tool = Path(sys.argv[1]), sys.argv[2]
    failures = []
    scratch = Path(tempfile.mkdtemp(prefix="toolpoint_docs_"))
    (scratch / "build").mkdir()
    (scratch / "build" / "toolpoint").symlink_to(tool)
    (scratch / "examples").symlink_to(source / "examples")
    env = dict(os.environ, TOOLPOINT_PROGRESS_DELAY="1000")

    def run(command, cwd):
        return subprocess.run(command, shell=True, cwd=cwd, capture_output=True, text=True, encoding="utf-8", env=env)

    docs = [source / "README.md", *sorted((source / "docs").glob("*.md"))]
    quoted = 0
    for doc in docs:
        text = doc.read_text(encoding="utf-8")
        for m in re.finditer(r"<!-- output of: (.+?) -->\n+```[a-z]*\n(.*?)```", text, re.S):
            command, block = m.group(1), m.group(2)
            r = run(command, scratch)
            if r.returncode != 0:
                failures.append(f"{doc.name}: `{command}` exited {r.returncode}: {r.stderr.strip()[-400:]}")
                continue
            lines = set(line.rstrip() for line in r.stdout.splitlines())
            for line in block.splitlines():
                if line.strip() and line.rstrip() not in lines:
                    failures.append(f"{doc.name}: the output of `{command}` has no line\n    {line.rstrip()}\n"
                                    f"  (the document quotes it: run the command and copy its output)")
            quoted += 1
    if quoted < 2:
        failures.append(f"expected at least 2 quoted outputs (the demo's, the plan's), found {quoted}")

    results = {}
    if (scratch / "demo" / "summary.json").exists():
        results["demo/summary.json"] = json.loads((scratch / "demo" / "summary.json").read_text(encoding="utf-8"))
    for name, phrase, kind, value in CLAIMS:
        text = flat((source / name).read_text(encoding="utf-8"))
        said = phrase.replace("{", "").replace("}", "")
        if said not in text:
            failures.append(f"{name} no longer says \"{said}\": update CLAIMS in tests/docs/check_quoted_output.py")
            continue
        try:
            actual = value(results)
        except (KeyError, IndexError, TypeError) as e:
            failures.append(f"{name}: \"{said}\": the result has no such value ({e!r})")
            continue
        if kind == "fact":
            if actual is not True:
                failures.append(f"{name}: \"{said}\" is no longer true")
            continue
        number = re.search(r"\{(.+?)\}", phrase).group(1)
        q, h = float(number), half_unit(number)
        ok = abs(actual - q) <= h if kind == "equal" else actual <= q + h
        if not ok:
            failures.append(f"{name}: \"{said}\" quotes {number}, the result is {actual:.6g} "
                            f"({'must round to it' if kind == 'equal' else 'must be at most it'})")

    readme = (source / "README.md").read_text(encoding="utf-8")
    tour = re.search(r"\n## A first tour\n.*?```sh\n(.*?)```", readme, re.S)
    if not tour:
        failures.append("README.md: no ```sh block under '## A first tour'")
    else:
        tour_dir = scratch / "tour"
        tour_dir.mkdir()
        (tour_dir / "build").symlink_to(scratch / "build")
        (tour_dir / "examples").symlink_to(source / "examples")
        (tour_dir / "tour.sh").write_text(tour.group(1))
        r = run("sh -e tour.sh", tour_dir)
        if r.returncode != 0:
            failures.append(f"README.md: the tour exited {r.returncode}: {r.stderr.strip()[-600:]}")

    for f in failures:
        print("FAIL:", f)
    if not failures:
        print(f"{quoted} quoted outputs, {len(CLAIMS)} numbers and facts in the text, and the README's tour agree with the tool")
        shutil.rmtree(scratch)
    else:
        print(f"(scratch folder kept: {scratch})")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
