#!/usr/bin/python3
"""Draws the paper-reproduction figures from the experiments' CSV files.

  scripts/plot_paper_figures.py [--normals-dir out/normals] [--runtime-dir out/runtime]
                                [--out-dir out/figures]

(a) normals_error.png: mean angular error (red) and +-sigma (blue) against the slope alpha, OVPC
    on top and PCA below, as in the paper's figure; from normals_ovpc.csv and normals_pca.csv
    written by build/bench/ovpc_normals_experiment.
(b) runtime_histograms.png: per-cloud map-building time of every method, from runtime_samples.csv
    written by build/bench/ovpc_runtime_comparison.

Needs Debian's python3-matplotlib and python3-numpy (scripts/install-deps --with-baselines); the
shebang names /usr/bin/python3 so that a python3 from elsewhere on PATH does not shadow them.
A figure whose input files are missing is skipped with a message; exit code 1 if none was drawn.
"""
import argparse
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def column(rows, name):
    return np.array([float(r[name]) for r in rows])


def plot_normals(normals_dir, out_path):
    series = []
    for name, file in (("OVPC vertex normals", "normals_ovpc.csv"),
                       ("PCA normals, r = 0.3 m", "normals_pca.csv")):
        path = os.path.join(normals_dir, file)
        if not os.path.exists(path):
            print(f"plot_paper_figures: {path} missing; skipping the normals figure")
            return False
        series.append((name, read_csv(path)))

    # One y range for both panels, so that they compare at a glance.
    top = 0.0
    bottom = 0.0
    for _, rows in series:
        top = max(top, float(np.max(column(rows, "mean_deg") + column(rows, "sd_deg"))))
        bottom = min(bottom, float(np.min(column(rows, "mean_deg") - column(rows, "sd_deg"))))
    fig, axes = plt.subplots(len(series), 1, figsize=(7.0, 6.0), sharex=True)
    for ax, (name, rows) in zip(axes, series):
        alpha = column(rows, "alpha_deg")
        mean = column(rows, "mean_deg")
        sd = column(rows, "sd_deg")
        ax.fill_between(alpha, mean - sd, mean + sd, color="tab:blue", alpha=0.2, linewidth=0)
        ax.plot(alpha, mean + sd, color="tab:blue", linewidth=0.8, label="mean ± σ")
        ax.plot(alpha, mean - sd, color="tab:blue", linewidth=0.8)
        ax.plot(alpha, mean, color="tab:red", linewidth=1.2, label="mean")
        ax.set_title(f"{name}: mean {mean.mean():.2f}°, mean σ {sd.mean():.2f}° over all slopes",
                     fontsize=10)
        ax.set_ylabel("angular error [°]")
        ax.set_ylim(bottom - 0.5, top * 1.05)
        ax.grid(True, linewidth=0.3)
        ax.legend(loc="upper right", fontsize=8)
    axes[-1].set_xlabel("slope α [°]")
    fig.suptitle("Normal estimation on noisy, misaligned bundled clouds", fontsize=11)
    fig.tight_layout()
    fig.savefig(out_path, dpi=150)
    plt.close(fig)
    print(f"wrote {out_path}")
    return True


# Colours after the paper's figure: OVPC red, OctoMap blue, elevation mapping green.
METHOD_STYLE = {
    "ovpc": ("OVPC", "tab:red"),
    "octomap_0.1": ("OctoMap 0.1 m", "#08306b"),
    "octomap_0.2": ("OctoMap 0.2 m", "#2171b5"),
    "octomap_0.3": ("OctoMap 0.3 m", "#6baed6"),
    "elevation_map": ("elevation map (project baseline)", "tab:green"),
}


def plot_runtime(runtime_dir, out_path):
    path = os.path.join(runtime_dir, "runtime_samples.csv")
    if not os.path.exists(path):
        print(f"plot_paper_figures: {path} missing; skipping the runtime figure")
        return False
    rows = read_csv(path)
    methods = []
    for r in rows:
        if r["method"] not in methods:
            methods.append(r["method"])
    times = {m: np.array([float(r["ms"]) for r in rows if r["method"] == m]) for m in methods}
    lo = min(float(t.min()) for t in times.values())
    hi = max(float(t.max()) for t in times.values())
    # Log-spaced bins: the methods differ by orders of magnitude.
    bins = np.logspace(np.log10(lo * 0.9), np.log10(hi * 1.1), 80)
    fig, ax = plt.subplots(figsize=(8.0, 4.5))
    for m in methods:
        label, colour = METHOD_STYLE.get(m, (m, None))
        t = times[m]
        ax.hist(t, bins=bins, color=colour, alpha=0.6,
                label=f"{label}: {t.mean():.2f} ± {t.std(ddof=1) if len(t) > 1 else 0.0:.2f} ms")
    ax.set_xscale("log")
    ax.set_xlabel("time per cloud [ms] (log scale)")
    ax.set_ylabel("runs")
    n = len(next(iter(times.values())))
    ax.set_title(f"Map building from one buffered cloud ({n} runs per method)", fontsize=11)
    ax.grid(True, which="both", linewidth=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out_path, dpi=150)
    plt.close(fig)
    print(f"wrote {out_path}")
    return True


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--normals-dir", default="out/normals")
    parser.add_argument("--runtime-dir", default="out/runtime")
    parser.add_argument("--out-dir", default="out/figures")
    args = parser.parse_args()
    os.makedirs(args.out_dir, exist_ok=True)
    drawn = plot_normals(args.normals_dir, os.path.join(args.out_dir, "normals_error.png"))
    drawn |= plot_runtime(args.runtime_dir, os.path.join(args.out_dir, "runtime_histograms.png"))
    return 0 if drawn else 1


if __name__ == "__main__":
    sys.exit(main())
