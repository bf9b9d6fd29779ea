# The lavapipe table of docs/benchmarks.md from four-passes.txt (run.sh):
# each round's sustained exact ms and passes; voxels from round 1.
import os, sys
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import gpu_bench_runs
rows = gpu_bench_runs.read(sys.argv[1])
print('| feature size | size | voxels | exact before, two rounds | exact after, two rounds |')
print('|---' * 5 + '|')
for k, v in rows.items():
    vox = v[('voxels', 'before')][0][0]
    cells = []
    for b in ('before', 'compact'):
        cells.append('; '.join(f"{e[0]:.0f} ({e[0] / vox:.2f}x: {' + '.join(f'{float(x):.0f}' for x in e[1][:3])})" for e in v[('exact', b)]))
    print(f"| {k[1]} | {k[2]} | {vox:.0f} | {cells[0]} | {cells[1]} |")
