# Prints the second table of docs/benchmarks.md from a run of run2.sh: the faster of two rounds.
# Voxels from the three builds; exact before (times its own voxels) and from the last
# build in the order listed (0) and long stretches first (4), times that build's voxels,
# with the passes (voxel pass + check + refinement).
import os, sys
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import gpu_bench_runs
rows = gpu_bench_runs.read(sys.argv[1])
print('| scene | feature size | size | voxels before | voxels, first run\'s build | voxels after | exact before | exact after, order listed | exact after, long first |')
print('|---' * 9 + '|')
for k, v in rows.items():
    vb, vo, va = (min(x[0] for x in v[('voxels', b)]) for b in ('before', 'order', 'after'))
    out = f"| {k[0]} | {k[1]} | {k[2]} | {vb:.3f} | {vo:.3f} | {va:.3f}"
    for var in ['before', '0', '4']:
        b = min(v[('exact', var)], key=lambda x: x[0])
        base = vb if var == 'before' else va
        out += f" | {b[0]:.3f} ({b[0] / base:.2f}x), {' + '.join(b[1][:3])}"
    print(out + ' |')
