"""The same-budget table of docs/results/odometry.md from `keylo compare --same-budget` outputs:
one row per data set × keypoint config, with its windows, `+random` and `+voxel-budget`
variants and the raw cloud of the same registrar side by side.

    python3 scripts/study/budget_table.py /tmp/study/cmp-lab /tmp/study/cmp-corridor ...

Cells: translation error mean (m) / rotation error mean (deg), or the verdict when a run did
not finish ok; rates are un-throttled odometry rates (Hz) and CPU (%) of windows / random /
voxel-budget / raw.
"""

import csv
import sys


def cell(row):
    verdict, reason = row["verdict"], row["reason"]
    if verdict == "failed" and "stopped at frame " in reason:
        frame = reason.split("stopped at frame ")[1].split(":")[0]
        return f"failed at frame {frame}"
    if verdict == "diverged" and reason.startswith("max APE "):
        return f"diverged ({reason.split(' >')[0]})"
    if verdict != "ok":
        return verdict
    if not row["trans_mean_m"]:
        return "ok, no APE"
    return f"{float(row['trans_mean_m']):.3f} / {float(row['rot_mean_deg']):.2f}°"


def number(row, key, fmt):
    value = row.get(key, "")
    return format(float(value), fmt) if value not in ("", None) else "–"


def main():
    print("| data | registrar | keypoints | points per frame | keypoint windows | random, same count"
          " | voxel-budget, same count | raw cloud | rate, Hz | CPU, % |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for folder in sys.argv[1:]:
        with open(f"{folder}/compare.csv", newline="") as f:
            rows = list(csv.DictReader(f))
        raw = {r["registrar"]: r for r in rows if r["variant"].startswith("raw-")}
        for base in (r for r in rows if "+" not in r["variant"] and not r["variant"].startswith("raw-")):
            name = base["variant"]
            random = next(r for r in rows if r["variant"] == f"{name} +random")
            voxel = next(r for r in rows if r["variant"] == f"{name} +voxel-budget")
            reference = raw.get(base["registrar"]) or raw.get("kiss-icp")
            trio = (base, random, voxel, reference)
            detector = "SuperPoint" if "superpoint" in name else "AKAZE"
            print(f"| {base['data']} | {base['registrar']} | {detector} | {number(base, 'mean_points', '.0f')}"
                  f" | {cell(base)} | {cell(random)} | {cell(voxel)}"
                  f" | {cell(reference)} ({reference['registrar']}) | "
                  + " / ".join(number(r, "odometry_hz", ".1f") for r in trio)
                  + " | " + " / ".join(number(r, "cpu_percent", ".0f") for r in trio) + " |")


if __name__ == "__main__":
    main()
