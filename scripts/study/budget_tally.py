"""How often the keypoint windows beat a random and a voxel-budget sample of the same point
count, over `keylo compare --same-budget` outputs: by the mean translation error, errors within
10 % of each other a tie; a run that did not finish ok loses to one that did, two that did not
are a tie.

    python3 scripts/study/budget_tally.py /tmp/study/cmp-*
"""

import csv
import sys

TIE = 0.1


def error(row):
    if row["verdict"] != "ok":
        return float("inf")
    return float(row["trans_mean_m"]) if row["trans_mean_m"] else None


def main():
    tally = {"random": [0, 0, 0], "voxel-budget": [0, 0, 0]}  # windows better, tie, worse
    for folder in sys.argv[1:]:
        with open(f"{folder}/compare.csv", newline="") as f:
            rows = {r["variant"]: r for r in csv.DictReader(f)}
        for name, base in rows.items():
            if "+" in name or name.startswith("raw-"):
                continue
            for other, counts in tally.items():
                a, b = error(base), error(rows[f"{name} +{other}"])
                if a is None or b is None:
                    continue  # ok without APE: nothing to compare
                tie = a == b or abs(a - b) <= TIE * min(a, b)
                counts[1 if tie else 0 if a < b else 2] += 1
    for other, (better, tie, worse) in tally.items():
        print(f"windows against {other}: better in {better}, tie in {tie}, worse in {worse}"
              f" of {better + tie + worse}")


if __name__ == "__main__":
    main()
