#!/usr/bin/env python3
"""Condensed comparison tables (markdown) from the JSON that `mvr bench sorbier|kalaiah|adelson
--save-json` wrote into bench/results/, next to the papers' own numbers (copied from the
papers' tables in ../shared/papers/). Usage: bench/summarize.py [RESULTS_DIR]"""
import json
import os
import sys

here = os.path.dirname(os.path.abspath(__file__))
results = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "results")

# sorbier2008 Table 1 (traditional, one-pass GS+MRT) and Table 2 (depth-map), fps, GeForce 8800 GTX.
SORBIER_T1 = {
    "flat": [(163, 304), (55, 108), (33, 65), (18, 36)],
    "vertex": [(83, 158), (28, 54), (16, 33), (9, 19)],
    "pixel": [(82, 156), (27, 54), (16, 33), (9, 18)],
}
SORBIER_T2 = {"flat": [158, 55, 33, 18], "vertex": [107, 36, 22, 12], "pixel": [105, 35, 22, 12]}
# kalaiah2007 Table 1, U/C fps ratio per configuration, for its six models.
KALAIAH = {
    "1x1": [(1338.6, 1002.1), (352.9, 319.2), (197.8, 140.0), (121.3, 100.8), (125.2, 94.6), (35.2, 26.6)],
    "2x1": [(752.8, 989.3), (186.2, 224.3), (100.2, 123.7), (62.1, 93.7), (63.6, 89.9), (17.7, 26.1)],
    "3x1": [(522.7, 969.2), (125.7, 170.8), (67.1, 87.3), (41.8, 65.6), (42.7, 61.4), (11.8, 19.9)],
    "2x2": [(383.6, 956.2), (94.9, 137.9), (50.5, 66.9), (31.5, 50.7), (32.1, 47.2), (8.8, 15.0)],
    "3x2": [(272.3, 543.6), (63.7, 99.8), (33.7, 47.2), (21.1, 34.7), (21.5, 32.2), (5.9, 10.1)],
    "3x3": [(184.5, 295.2), (42.6, 70.6), (22.5, 32.3), (14.1, 23.6), (14.3, 21.8), (3.9, 6.8)],
}


def load(name):
    with open(os.path.join(results, name + ".json")) as f:
        return json.load(f)


def find(rows, **kw):
    for r in rows:
        if all(r.get(k) == v for k, v in kw.items()):
            return r
    return None


def sorbier():
    j = load("sorbier")
    rows = j["results"]
    tris = sorted({r["triangles"] for r in rows})
    gl_one_pass = sorted({r["method"] for r in rows if r["backend"] == "gl" and r["method"] != "multipass"})
    print("| shading | triangles | soft multipass fps | soft unified fps (×) | gl multipass fps | gs-mrt fps (×) | "
          "gs-depthmap fps (×) | best gl one-pass (×) | paper: trad. / one-pass fps (×) | paper Table 2 depth-map fps (×) |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for shading in ["flat", "vertex", "pixel"]:
        for i, t in enumerate(tris):
            def cell(backend, method):
                r = find(rows, backend=backend, method=method, shading=shading, triangles=t)
                if not r or "error" in r:
                    return "n/a"
                return f"{r['fps']:.1f} ({r['speedup_vs_multipass']:.2f}×, cpu {r['cpu_speedup_vs_multipass']:.2f}×)"
            sm = find(rows, backend="soft", method="multipass", shading=shading, triangles=t)
            gm = find(rows, backend="gl", method="multipass", shading=shading, triangles=t)
            best = None
            for m in gl_one_pass:
                r = find(rows, backend="gl", method=m, shading=shading, triangles=t)
                if r and "error" not in r and (best is None or r["fps"] > best["fps"]):
                    best = r
            bestc = f"{best['method']} {best['fps']:.1f} ({best['speedup_vs_multipass']:.2f}×)" if best else "n/a"
            p1 = SORBIER_T1[shading][i] if i < 4 else None
            p2 = SORBIER_T2[shading][i] if i < 4 else None
            paper1 = f"{p1[0]} / {p1[1]} ({p1[1] / p1[0]:.2f}×)" if p1 else "-"
            paper2 = f"{p2} ({p2 / p1[0]:.2f}×)" if p2 else "-"
            print(f"| {shading} | {t} | {sm['fps']:.1f} | {cell('soft', 'unified')} | {gm['fps']:.1f} | "
                  f"{cell('gl', 'gs-mrt')} | {cell('gl', 'gs-depthmap')} | {bestc} | {paper1} | {paper2} |")


def kalaiah():
    j = load("kalaiah")
    rows = j["results"]
    models = []
    for r in rows:
        if r["model"] not in models:
            models.append(r["model"])
    configs = ["1x1", "2x1", "3x1", "2x2", "3x2", "3x3"]
    head = "| model (triangles) | " + " | ".join(configs) + " |"
    print("U/C = fps of the one-pass method / fps of multipass on the same backend (wall; CPU-time ratio in brackets)\n")
    print(head)
    print("|---" * (len(configs) + 1) + "|")
    for backend, method in [("soft", "unified"), ("gl", "kalaiah-emulation"), ("gl", "instanced-layer")]:
        print(f"| **{backend}:{method}** |" + " |" * len(configs))
        for m in models:
            cells = []
            tri = ""
            for c in configs:
                r = find(rows, backend=backend, method=method, model=m, config=c)
                if r is None:
                    cells.append("-")
                    continue
                tri = r["triangles"]
                cells.append("n/a" if "error" in r else
                             f"{r['speedup_vs_multipass']:.2f} ({r['cpu_speedup_vs_multipass']:.2f})")
            print(f"| {m} ({tri}) | " + " | ".join(cells) + " |")
    print("| **paper (emulation U vs conventional C, Sharp Actius AL3D laptop), U/C over its 6 models: min–max** |" + "".join(
        f" {min(u / c for c, u in KALAIAH[k]):.2f}–{max(u / c for c, u in KALAIAH[k]):.2f} |" for k in configs))


def adelson():
    j = load("adelson")
    print("| algorithm | workload | I ops | I time | II ops | II time | III ops | III time | paper I / II / III |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in j["results"]:
        o, t, p = r["savings_ops"], r["savings_time"], r["paper"]
        interp = r.get("savings_interpolations")
        io = f"{100 * o['I']:.1f}%" + (f" (interp. {100 * interp['I']:.1f}%)" if interp else "")
        print(f"| {r['algorithm']} | {r['case']} | {io} | {100 * t['I']:.1f}% | {100 * o['II']:.1f}% | "
              f"{100 * t['II']:.1f}% | {o['III']:.2f} | {t['III']:.2f} | {p['I']} / {p['II']} / {p['III']} |")


if __name__ == "__main__":
    for name, fn in [("sorbier", sorbier), ("kalaiah", kalaiah), ("adelson", adelson)]:
        if os.path.exists(os.path.join(results, name + ".json")):
            print(f"\n### {name}\n")
            fn()
