# Reads the output of a device run script under bench/results: lines
# "== round R SCENE FS QUALITY VARIANT" followed by kerf_gpu_bench's rows.
# Returns {(scene, feature size, image size): {(quality, variant): [(sustained ms,
# (voxel pass, check, refinement, pixels refined) or None), ...]}}, one entry per round.
import re


def read(path):
    rows = {}
    cur = None
    for line in open(path):
        m = re.match(r'== round (\d) (\w+) ([\d.]+) (\w+) (\w+)', line)
        if m:
            cur = m.groups()
            continue
        if not line.strip() or cur is None:
            continue
        parts = line.split()
        p = re.search(r'passes ([\d.]+) \+ ([\d.]+) \+ ([\d.]+) ms, (\d+) pixels', line)
        rows.setdefault((cur[1], cur[2], parts[6]), {}).setdefault((cur[3], cur[4]), []).append(
            (float(parts[10]), p.groups() if p else None))
    return rows
