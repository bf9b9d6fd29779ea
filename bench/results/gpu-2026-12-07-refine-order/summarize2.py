# Prints the second table of docs/benchmarks.md from a run of run2.sh: the faster of two rounds.
# Voxels from the three builds; exact before (times its own voxels) and from the last
# build in the order listed (0) and long stretches first (4), times that build's voxels,
# with the passes (voxel pass + check + refinement).
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
    p = re.search(r'passes ([\d.]+) \+ ([\d.]+) \+ ([\d.]+) ms', line)
    rows.setdefault((cur[1], cur[2], parts[6]), {}).setdefault((cur[3], cur[4]), []).append((float(parts[10]), p.groups() if p else None))
print('| scene | feature size | size | voxels before | voxels, first run\'s build | voxels after | exact before | exact after, order listed | exact after, long first |')
print('|---' * 9 + '|')
for k, v in rows.items():
    vb, vo, va = (min(x[0] for x in v[('voxels', b)]) for b in ('before', 'order', 'after'))
    out = f"| {k[0]} | {k[1]} | {k[2]} | {vb:.3f} | {vo:.3f} | {va:.3f}"
    for var in ['before', '0', '4']:
        b = min(v[('exact', var)], key=lambda x: x[0])
        base = vb if var == 'before' else va
        out += f" | {b[0]:.3f} ({b[0] / base:.2f}x), {' + '.join(b[1])}"
    print(out + ' |')
