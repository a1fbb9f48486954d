#!/usr/bin/env python3
"""Error against bytes for a set of bakes of one mesh, notebook-style.

    python3 examples/python/error_vs_bytes.py MESH OUTDIR [--mm-per-unit S] [--quick]

Bakes MESH at a few storage settings with sss-bake, reads each file with the
`sss` package (common/python, docs/python.md), measures it three ways and
plots error against bytes per vertex: OUTDIR/error_vs_bytes.{csv,png}.
Tools: $SSS_BAKE / $SSS_STAT or sss-bake / sss-stat on PATH; gnuplot for
the plot. Each cell below ("# %%") runs as it stands in a notebook.
"""
# %% set-up
import argparse
import csv
import os
import subprocess
import sys

import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "common", "python"))
import sss  # noqa: E402

ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
ap.add_argument("mesh")
ap.add_argument("outdir")
ap.add_argument("--mm-per-unit", default="20")
ap.add_argument("--material", default="marble")
ap.add_argument("--quick", action="store_true", help="50 directions and 10 error views (a test run)")
args = ap.parse_args()
os.makedirs(args.outdir, exist_ok=True)
bake = os.environ.get("SSS_BAKE", "sss-bake")
dirs, views = ("50", "10") if args.quick else ("200", "100")

# %% the bakes: the defaults, then one storage knob at a time (docs/accuracy.md)
configs = {
    "float": ["--quant", "float"],
    "lloyd8": ["--quant", "lloyd8"],
    "defaults": [],
    "sh-order 2": ["--sh-order", "2"],
    "refs 3%": ["--refs", "0.03"],
    "paper": ["--preset", "paper"],
}
files = {}
for name, extra in configs.items():
    path = os.path.join(args.outdir, name.replace(" ", "_").replace("%", "") + ".sss")
    # the paper's preset fixes its own 200 directions
    ndirs = [] if name == "paper" else ["--dirs", dirs]
    subprocess.run([bake, args.mesh, "-o", path, "--material", args.material, "--mm-per-unit", args.mm_per_unit,
                    "-q", *ndirs, *extra], check=True)
    files[name] = path

# %% measure: bytes from the file, error of the stored rows against the float
# bake (sss.decode_error), and against the exact evaluator (sss-stat --error)
rows = []
with sss.open(files["float"]) as ref:
    for name, path in files.items():
        with sss.open(path) as a:
            info = a.info
            same_rows = info["ndirs"] == ref.info["ndirs"] and info["near_terms"] == ref.info["near_terms"]
            vs_float = sss.decode_error(a, ref, ndirs=int(views))["rms"][-1] if same_rows else float("nan")
            q = a.decode([0.3, 0.4, 0.87])
        exact = sss.stat(path, "--error", "--views", views, "--no-image")["vertex_error"]["rms_all"]
        rows.append((name, info["integral_bytes_per_vertex"], vs_float, exact, float(np.mean(q))))
        print(f"{name:12s} {rows[-1][1]:8.1f} B/vertex  rms vs float {vs_float:.3e}  vs exact {exact:.3e}")

# %% write the table and plot it
csv_path = os.path.join(args.outdir, "error_vs_bytes.csv")
with open(csv_path, "w", newline="") as fh:
    w = csv.writer(fh)
    w.writerow(["config", "bytes_per_vertex", "rms_vs_float", "rms_vs_exact", "mean_q"])
    w.writerows(rows)
png = os.path.join(args.outdir, "error_vs_bytes.png")
plot = f"""set terminal pngcairo size 720,480
set output '{png}'
set datafile separator ','
set logscale xy
set xlabel 'bytes per vertex (integrals)'
set ylabel 'per-vertex RMS of q against the exact evaluator'
set key off
plot '{csv_path}' every ::1 using 2:4 with points pt 7 ps 1.5, \\
     '' every ::1 using 2:4:1 with labels offset 1,1 left
"""
subprocess.run(["gnuplot"], input=plot, text=True, check=True)
print(f"wrote {csv_path} and {png}")
