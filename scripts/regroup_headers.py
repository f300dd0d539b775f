#!/usr/bin/python3
"""Groups the public headers by pipeline stage (issue 26): include/toolpoint/X.hpp moves to
include/toolpoint/<stage>/X.hpp by the table below, and every mention of the old path is rewritten
in the tracked text files of the tree (code, CMake, docs, scripts): `#include "toolpoint/X.hpp"`,
`<toolpoint/X.hpp>`, `include/toolpoint/X.hpp`, `../include/toolpoint/X.hpp`, `toolpoint/X.hpp` in
prose. Bare names (`plot.hpp`'s figures) are left as they are: they still name the header.

Idempotent: a header already moved is not moved again, and a path already rewritten
(`toolpoint/model/beam.hpp`) no longer matches, so the script can run again on a tree that gained
new `#include "toolpoint/X.hpp"` lines (another branch merged after the move):

    /usr/bin/python3 scripts/regroup_headers.py            # move and rewrite, in the repository root
    /usr/bin/python3 scripts/regroup_headers.py --check    # change nothing; exit 1 if anything would,
                                                           # or if a header includes a later stage's

Run from anywhere: it works on the repository it is in (found with git). Moves go through `git mv`
so history follows the files. A top-level header that is neither in the table nor in KEEP stops the
script before anything changes: add its row (its stage) to TABLE, or its name to KEEP.
CHANGELOG.md is history and keeps the paths it was written with.
"""

import argparse
import os
import re
import subprocess
import sys

# stage → the headers of include/toolpoint/ that belong to it (the pipeline of docs/architecture.md),
# in pipeline order: a header may include its own stage's headers and earlier stages', never a later
# one's (--check enforces it; the test Headers.GroupedByStage runs --check).
STAGES = {
    # the structure's model: receptance blocks, Timoshenko segments, coupling, joints, the assembly
    "model": ["receptance", "beam", "coupling", "joint", "assembly"],
    # measured FRFs and what is done to them before identification: filtering, finite differences,
    # noise, resampling, peaks
    "measured": ["signal", "noise", "resample", "peaks"],
    # joints from FRFs: the closed form, the band fit, the forward check, the identified joint
    "identify": ["identify", "joint_fit", "forward_check", "identified_joint"],
    # chatter: modal fit, lobes and the time-domain boundary, full-discretization, the simulated cut
    "stability": ["modal_fit", "stability", "periodic_delay", "simulation"],
    # the joint's uncertainty carried to the FRF and the lobes
    "uncertainty": ["uncertainty"],
    # figures through gnuplot
    "plot": ["plot"],
    # files: CSV/UFF/CutPro FRFs, the assembly and joint files, the tables each stage writes
    "io": ["io", "uff", "frf_file", "assembly_file", "joint_file", "identify_io", "stability_io", "uncertainty_io"],
}
# Stay in include/toolpoint/: used by every stage (units and conventions, errors, threads,
# plausible ranges, quantiles, the option fields' definitions), or above all of them (json: every
# result type), or generated (version.hpp, by CMake). include/toolpoint/studies/ is already its own
# stage, after io.
KEEP = {"conventions", "error", "parallel", "plausibility", "statistics", "option_fields", "json", "version"}
# Layer order for the include check: the KEEP headers used by every stage first, json last.
ORDER = ["(top)"] + list(STAGES) + ["studies", "json"]

TABLE = {name: stage for stage, names in STAGES.items() for name in names}
SKIP_FILES = {"CHANGELOG.md"}


def git(root, *args):
    return subprocess.run(["git", "-C", root, *args], check=True, capture_output=True, text=True).stdout


def path_pattern():
    # toolpoint/NAME.hpp where `toolpoint/` starts a path (after a quote, <, a blank, a backtick,
    # "(") or follows include/ (../include/, ${prefix}/include/): never apps/toolpoint/X.hpp or
    # toolpoint/studies/X.hpp.
    names = "|".join(sorted(TABLE, key=len, reverse=True))
    return re.compile(r"(?:(?<=include/)|(?<![\w/.\-]))toolpoint/(" + names + r")\.hpp(?![\w])")


def rewrites_in(root):
    """(path, new text, number of paths) for each tracked text file that mentions an old path."""
    pattern = path_pattern()
    tracked = git(root, "ls-files", "-z", "--cached", "--others", "--exclude-standard").split("\0")
    rewrites = []
    for rel in tracked:
        if not rel or os.path.basename(rel) in SKIP_FILES:
            continue
        path = os.path.join(root, rel)
        if not os.path.isfile(path) or os.path.islink(path):
            continue
        try:
            with open(path, encoding="utf-8", newline="") as f:
                text = f.read()
        except (UnicodeDecodeError, OSError):
            continue  # binary data
        new_text = pattern.sub(lambda m: f"toolpoint/{TABLE[m.group(1)]}/{m.group(1)}.hpp", text)
        if new_text != text:
            rewrites.append((path, new_text, len(pattern.findall(text))))

    return rewrites


def stage_of(include_path):
    """The layer of a header given as its path under include/ ("toolpoint/model/beam.hpp")."""
    parts = include_path.split("/")[1:]
    if len(parts) > 1:
        return parts[0]
    return "json" if parts[0] == "json.hpp" else "(top)"


def wrong_way_includes(root):
    """Each public header's include of a later stage's header, as "header -> included"."""
    out = []
    inc_root = os.path.join(root, "include")
    for dirpath, _, files in os.walk(os.path.join(inc_root, "toolpoint")):
        for f in sorted(files):
            if not f.endswith(".hpp"):
                continue
            path = os.path.join(dirpath, f)
            here = stage_of(os.path.relpath(path, inc_root).replace(os.sep, "/"))
            with open(path, encoding="utf-8") as h:
                for included in re.findall(r'^\s*#\s*include\s*[<"](toolpoint/[^">]+)[">]', h.read(), re.M):
                    there = stage_of(included)
                    if here in ORDER and there in ORDER and ORDER.index(there) > ORDER.index(here):
                        out.append(f"{os.path.relpath(path, root)} -> {included}")
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="change nothing; exit 1 if anything would change")
    args = parser.parse_args()

    here = os.path.dirname(os.path.abspath(__file__))
    try:
        root = git(here, "rev-parse", "--show-toplevel").strip()
    except (OSError, subprocess.CalledProcessError):
        print("regroup_headers: not a git checkout (it lists the files through git): skipped")
        sys.exit(77)  # ctest's skip code (SKIP_RETURN_CODE)
    inc = os.path.join(root, "include", "toolpoint")

    unknown = sorted(f[:-4] for f in os.listdir(inc)
                     if f.endswith(".hpp") and f[:-4] not in TABLE and f[:-4] not in KEEP)
    if unknown:
        sys.exit("regroup_headers: no stage for include/toolpoint/{}: add each to STAGES (or KEEP) in "
                 "scripts/regroup_headers.py".format(", ".join(u + ".hpp" for u in unknown)))

    moves = []
    for name, stage in sorted(TABLE.items()):
        old = os.path.join(inc, name + ".hpp")
        new = os.path.join(inc, stage, name + ".hpp")
        if os.path.exists(old) and os.path.exists(new):
            sys.exit(f"regroup_headers: both include/toolpoint/{name}.hpp and include/toolpoint/{stage}/{name}.hpp "
                     "exist: merge them by hand, then run again")
        if os.path.exists(old):
            moves.append((old, new))

    if args.check:
        rewrites = rewrites_in(root)
        for old, new in moves:
            print(f"would move {os.path.relpath(old, root)} -> {os.path.relpath(new, root)}")
        for path, _, n in rewrites:
            print(f"would rewrite {n} path(s) in {os.path.relpath(path, root)}")
        wrong = [] if moves else wrong_way_includes(root)
        for w in wrong:
            print(f"includes a later stage: {w} (stages in order: {', '.join(ORDER)})")
        if moves or rewrites:
            print("run /usr/bin/python3 scripts/regroup_headers.py to group them")
        sys.exit(1 if moves or rewrites or wrong else 0)

    for old, new in moves:
        os.makedirs(os.path.dirname(new), exist_ok=True)
        rel_old = os.path.relpath(old, root)
        if subprocess.run(["git", "-C", root, "ls-files", "--error-unmatch", rel_old],
                          capture_output=True).returncode == 0:
            git(root, "mv", rel_old, os.path.relpath(new, root))
        else:
            os.replace(old, new)
        print(f"moved {rel_old} -> {os.path.relpath(new, root)}")
    rewrites = rewrites_in(root)  # after the moves: the moved headers are rewritten where they now are
    for path, new_text, n in rewrites:
        with open(path, "w", encoding="utf-8", newline="") as f:
            f.write(new_text)
        print(f"rewrote {n} path(s) in {os.path.relpath(path, root)}")
    if not moves and not rewrites:
        print("regroup_headers: nothing to do (already grouped)")


if __name__ == "__main__":
    main()
