#!/usr/bin/env python3
"""Issue 18's acceptance runs: runs a scenario (kidnap_stress, global_start_expo,
global_start_office) over seeds and pools the per-kidnap outcomes of the global
localization and its MCL shadow (a global start is a kidnap at 0 s).

usage: scripts/kidnap_stress_sweep.py PAVILION OUT_DIR [--seeds 1-10] [--duration S]
"""
import argparse, json, os, statistics, subprocess, sys


def pooled(outcomes, figures):
    n = len(outcomes)
    rec = [k for k in outcomes if k.get("recovered")]
    lost10 = [k for k in outcomes if k.get("lost_declared") and k.get("motion_to_lost_s", 1e9) <= 10.0]
    t_rel = [k["time_to_relocalize_s"] for k in rec if "time_to_relocalize_s" in k]
    d_rel = [k["distance_to_relocalize_m"] for k in rec if "distance_to_relocalize_m" in k]
    t_lost = [k["motion_to_lost_s"] for k in outcomes if "motion_to_lost_s" in k]
    fbt = [k for k in outcomes if k.get("fbt_recovered")]
    within60 = [k for k in outcomes
                if k.get("localized_correctly") and k.get("motion_to_correct_s", 1e9) <= 60.0]
    false = sum(f.get("false_relocalizations", 0) for f in figures)
    med = lambda v: round(statistics.median(v), 2) if v else None
    return {"kidnaps": n, "recovered_ratio": round(len(rec) / n, 4) if n else None,
            "lost_declared_within_10s_ratio": round(len(lost10) / n, 4) if n else None,
            "false_relocalizations": false,
            "false_relocalization_ratio": round(false / n, 4) if n else None,
            "median_time_to_lost_s": med(t_lost), "median_time_to_relocalize_s": med(t_rel),
            "median_distance_to_relocalize_m": med(d_rel),
            "fbt_recovered_ratio": round(len(fbt) / n, 4) if n else None,
            "localized_within_60s_ratio": round(len(within60) / n, 4) if n else None}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("pavilion"); ap.add_argument("out")
    ap.add_argument("--seeds", default="1-10"); ap.add_argument("--duration", type=float)
    ap.add_argument("--scenario", default="scenarios/kidnap_stress.yaml")
    a = ap.parse_args()
    lo, hi = (int(x) for x in a.seeds.split("-"))
    ours, theirs, fo, ft = [], [], [], []
    for seed in range(lo, hi + 1):
        out = os.path.join(a.out, f"seed_{seed}")
        if not os.path.exists(os.path.join(out, "metrics.json")):  # resumes
            cmd = [a.pavilion, "run", a.scenario, "--out", out, "--seed", str(seed), "--threads", "1"]
            if a.duration: cmd += ["--duration", str(a.duration)]
            subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
        m = json.load(open(os.path.join(out, "metrics.json")))
        for r in m["robots"].values():
            if "relocalization" in r:
                ours += r["relocalization"]["per_kidnap"]; fo.append(r["relocalization"])
            s = r.get("shadow", {}).get("relocalization")
            if s:
                theirs += s["per_kidnap"]; ft.append(s)
    print(json.dumps({"global_localization": pooled(ours, fo), "mcl_shadow": pooled(theirs, ft)}, indent=1))


if __name__ == "__main__":
    sys.exit(main())
