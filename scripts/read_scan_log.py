#!/usr/bin/env python3
"""Reads a Pavilion scan log (scans.bin, format in docs/scan_log.md).

Usage: read_scan_log.py scans.bin [--summary]
As a module: for rec in read_scan_log(path): rec["ranges"], rec["truth"], ...
"""
import struct
import sys


def read_scan_log(path):
    data = open(path, "rb").read()
    if data[:8] != b"PAVSCAN1":
        raise ValueError(f"{path}: not a Pavilion scan log")
    pos = 8

    def take(fmt):
        nonlocal pos
        values = struct.unpack_from("<" + fmt, data, pos)
        pos += struct.calcsize("<" + fmt)
        return values

    def string():
        (n,) = take("H")
        return take(f"{n}s")[0].decode()

    (count,) = take("I")
    elements = [string() for _ in range(count)]
    records = []
    while pos < len(data):
        take("I")  # record size
        rec = {"robot": string(), "sensor": string()}
        rec["stamp_s"], rec["max_range_m"], mx, my, mt = take("5d")
        rec["robot_from_sensor"] = (mx, my, mt)
        (n,) = take("I")
        readings = [take("fffB") for _ in range(n)]
        rec["bearing_rad"] = [r[0] for r in readings]
        rec["range_m"] = [r[1] for r in readings]
        rec["time_offset_s"] = [r[2] for r in readings]
        rec["valid"] = [bool(r[3] & 1) for r in readings]
        rec["reflector"] = [bool(r[3] & 2) for r in readings]
        (has_truth,) = take("B")
        if has_truth:
            truth = [take("ddffi") for _ in range(n)]
            rec["true_sensor_pose"] = [(t[0], t[1], t[2]) for t in truth]
            rec["true_range_m"] = [t[3] for t in truth]
            rec["element"] = [elements[t[4]] if t[4] >= 0 else None for t in truth]
        records.append(rec)
    return elements, records


if __name__ == "__main__":
    elements, records = read_scan_log(sys.argv[1])
    print(f"{len(records)} scans, {len(elements)} world elements")
    for rec in records[:3]:
        valid = sum(rec["valid"])
        print(f"  {rec['robot']}/{rec['sensor']} t={rec['stamp_s']:.3f} s: "
              f"{len(rec['range_m'])} readings, {valid} valid, {sum(rec['reflector'])} reflector")
