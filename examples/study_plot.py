#!/usr/bin/env python3
"""A built-in study at its --quick size, its results.csv in pandas, one plot with matplotlib.

  python examples/study_plot.py [--study spatial-neighbors-pt] [--out out/py-study] [--full]
The study is the CLI's (`restir study NAME --out OUT`): resumable, references cached, report.html
beside the CSV. Writes OUT/python-plot.png.
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import restirlab as rl  # noqa: E402


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--study", default="spatial-neighbors-pt")
    p.add_argument("--out", default="out/py-study")
    p.add_argument("--full", action="store_true", help="the study's full size (minutes to hours), not --quick")
    args = p.parse_args()
    result = rl.study(args.study, args.out, quick=not args.full)
    df = result.to_pandas()
    print(df.head())
    # The swept key: an option column (dotted) whose value changes between rows, the seed aside.
    axis = next(c for c in df.columns if "." in c and c != "render.seed" and df[c].nunique() > 1)
    table = df.groupby(["scene", axis])["relmse"].mean().unstack("scene")
    ax = table.plot(marker="o", logy=True, title=f"{args.study}: relMSE")
    ax.set_ylabel("relMSE")
    plt.tight_layout()
    plt.savefig(f"{args.out}/python-plot.png", dpi=100)
    print(f"wrote {args.out}/python-plot.png; the study's own report: {result.report}")


if __name__ == "__main__":
    main()
