#!/usr/bin/env python3
"""model_error_exit.py ROWS.jsonl [ETA]: the model-error table of
docs/accuracy.md ("What the truth shows", 1.) for both exit terms, from the
per-vertex rows tests/bench/model_error.sh stores (sss-stat --model-error
--json). The normalised exit (sss-view/sss-stat --exit normalised) divides
the real-time radiance by c(eta) = 2 int_0^1 F_t(eta, mu) mu dmu and leaves
the reference as it is, so each row's normalised columns follow from its
Jensen ones exactly (tests/integration/cli_reference.sh checks that
relation on the tools). Ratio: mean real-time over mean reference; rel. RMS:
sqrt(sum (L_rt - L_ref)^2 - sum se^2) / sqrt(sum L_ref^2), as sss-stat."""
import json
import math
import sys


def ft(eta, c):
    """docs/physics.md section 3, as common/src/dipole.c's sss_ft."""
    if c <= 0:
        return 0.0
    c = min(c, 1.0)
    g2 = eta * eta - 1 + c * c
    if g2 < 0:
        return 0.0
    g = math.sqrt(g2)
    a = (g - c) / (g + c)
    b = (c * (g + c) - 1) / (c * (g - c) + 1)
    return 1 - min(1.0, 0.5 * a * a * (1 + b * b))


def exit_norm(eta, n=4096):
    return 2 * sum(ft(eta, (k + 0.5) / n) * (k + 0.5) / n for k in range(n)) / n


def columns(rows, scale):
    ratio, rms = [], []
    for c in range(3):
        rt = sum(v["realtime"][c] * scale for v in rows)
        ref = sum(v["reference"][c] for v in rows)
        d2 = sum((v["realtime"][c] * scale - v["reference"][c]) ** 2 - v["reference_stderr"][c] ** 2 for v in rows)
        r2 = sum(v["reference"][c] ** 2 for v in rows)
        ratio.append(rt / ref if ref > 0 else float("nan"))
        rms.append(math.sqrt(max(d2, 0.0) / r2) if r2 > 0 else float("nan"))
    return ratio, rms


def fmt(xs):
    return " / ".join("%.3f" % x for x in xs)


def main():
    eta = float(sys.argv[2]) if len(sys.argv) > 2 else 1.3
    c = exit_norm(eta)
    print("exit normalisation c(%.2f) = %.5f" % (eta, c))
    print()
    print("| case | ratio: jensen | ratio: normalised | rel. RMS: jensen | rel. RMS: normalised |")
    print("|---|---|---|---|---|")
    for line in open(sys.argv[1]):
        row = json.loads(line)
        pv = row["per_vertex"]
        rj, mj = columns(pv, 1.0)
        rn, mn = columns(pv, 1.0 / c)
        print("| %s | %s | %s | %s | %s |" % (row["case"], fmt(rj), fmt(rn), fmt(mj), fmt(mn)))


if __name__ == "__main__":
    main()
