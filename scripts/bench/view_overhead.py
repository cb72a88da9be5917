"""What watching or recording a run costs (docs/results/view.md): `keylo run` frames per second
without a viewer, with `--view` and no client, with `--view` and a client subscribed to every
topic (scripts/view/ws-client.mjs, npm's @foxglove/ws-protocol, on the same machine) at the
default `--view-hz 10` and at every frame (`--view-hz 0`), and with `--record`; each configuration's modes interleaved, REPS times, medians, ratios to the plain run
measured in the same invocation.

    python3 scripts/bench/view_overhead.py [--frames 150] [--reps 3] [--out /tmp/viewbench]

KEYLO: the binary (default target/release/keylo). Needs `npm ci` in scripts/view.
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
KEYLO = os.environ.get("KEYLO", str(ROOT / "target" / "release" / "keylo"))
CONFIGS = ["configs/paper/raw-kiss-icp.toml", "configs/paper/indoor-akaze-kiss-icp.toml"]
MODES = ["plain", "view, no client", "view, client", "view, client, every frame", "record"]


def run(config, data, out, mode, work):
    cmd = [KEYLO, "run", str(ROOT / config), "--data", str(data), "--out", str(out), "-q"]
    client = None
    mcap = work / "run.mcap"
    if mode.startswith("view"):
        cmd += ["--view", "127.0.0.1:0"]
        if mode.startswith("view, client"):
            cmd += ["--view-wait", "60"]
        if mode.endswith("every frame"):
            cmd += ["--view-hz", "0"]
    if mode == "record":
        cmd += ["--record", str(mcap)]
    err = open(work / "keylo.err", "w")
    proc = subprocess.Popen(cmd, stderr=err)
    if mode.startswith("view, client"):
        url = None
        for _ in range(600):
            m = re.search(r"ws://127\.0\.0\.1:\d+", (work / "keylo.err").read_text())
            if m:
                url = m.group(0)
                break
            time.sleep(0.05)
        client = subprocess.Popen(["node", str(ROOT / "scripts/view/ws-client.mjs"), url,
                                   str(work / "client.json"), "all"])
    if proc.wait() != 0:
        raise SystemExit(f"{' '.join(cmd)} failed: {(work / 'keylo.err').read_text()}")
    received, client_cpu = 0, 0.0
    if client:
        _, _, usage = os.wait4(client.pid, 0)
        client.returncode = 0
        client_cpu = usage.ru_utime + usage.ru_stime
        received = sum(json.loads((work / "client.json").read_text())["topics"].values())
    size = mcap.stat().st_size if mode == "record" else 0
    mcap.unlink(missing_ok=True)
    summary = json.loads((out / "summary.json").read_text())
    # The client's CPU per second of the run (it runs on the same cores).
    seconds = summary["frames"] / summary["wall_hz"]
    return summary["wall_hz"], received, size, client_cpu / seconds


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--frames", type=int, default=150)
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--out", type=Path, default=Path("/tmp/viewbench"))
    args = ap.parse_args()
    work = args.out
    work.mkdir(parents=True, exist_ok=True)
    data = work / "lab"
    if not (data / "gt.tum").exists():
        subprocess.run([KEYLO, "-q", "sim", "--scene", "lab", "--frames", str(args.frames), "--out", str(data)],
                       check=True)
    hz = {(c, m): [] for c in CONFIGS for m in MODES}
    extra = {}
    for rep in range(args.reps):
        for c in CONFIGS:
            for m in MODES:
                rate, received, size, cpu = run(c, data, work / "out", m, work)
                hz[(c, m)].append(rate)
                extra[(c, m)] = (received, size, cpu)
                print(f"rep {rep}: {Path(c).stem:24} {m:16} {rate:7.2f} Hz", flush=True)
    print(f"\n{args.frames} frames of the simulated lab (1024×128), {args.reps} runs each, median frames/s; "
          f"keylo {KEYLO}\n")
    print("| config | mode | frames/s | vs. plain | messages to the client | client CPU (cores) | MCAP MB |")
    print("|---|---|---|---|---|---|---|")
    for c in CONFIGS:
        base = statistics.median(hz[(c, "plain")])
        for m in MODES:
            med = statistics.median(hz[(c, m)])
            received, size, cpu = extra[(c, m)]
            print(f"| {Path(c).stem} | {m} | {med:.2f} | {med / base:.3f} | {received or ''} | "
                  f"{f'{cpu:.2f}' if received else ''} | {f'{size / 1e6:.0f}' if size else ''} |")


if __name__ == "__main__":
    main()
