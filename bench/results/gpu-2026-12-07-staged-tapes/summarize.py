# Prints the table of docs/benchmarks.md from a run of run.sh: the faster of two rounds.
import re, sys
rows = {}
cur = None
for line in open(sys.argv[1]):
    m = re.match(r'== round (\d) (\w+) ([\d.]+) (\w+) (\w+)', line)
    if m:
        cur = m.groups()
        continue
    if not line.strip() or cur is None:
        continue
    parts = line.split()
    p = re.search(r'passes ([\d.]+) \+ ([\d.]+) \+ ([\d.]+) ms, (\d+) pixels', line)
    rows.setdefault((cur[1], cur[2], parts[6]), {}).setdefault((cur[3], cur[4]), []).append((float(parts[10]), p.groups() if p else None))
for key, v in rows.items():
    vox = min(x[0] for x in v[('voxels', 'after')])
    out = f"| {key[0]} | {key[1]} | {key[2]} | {vox:.3f}"
    for var in ['before', 'after']:
        best = min(v[('exact', var)], key=lambda x: x[0])
        out += f" | {best[0]:.3f} ({best[0] / vox:.2f}x), {' + '.join(best[1][:3])}"
    print(out + " |")
