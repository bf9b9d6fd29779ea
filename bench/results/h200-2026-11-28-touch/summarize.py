# Prints the table of docs/benchmarks.md from a run of run.sh: the faster of two rounds.
import os, sys
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import gpu_bench_runs
rows = gpu_bench_runs.read(sys.argv[1])
for key, v in rows.items():
    vox = min(x[0] for x in v[('voxels', 'run')])
    out = f"| {key[0]} | {key[1]} | {key[2]} | {vox:.3f}"
    for var in ['run', 'touch']:
        best = min(v[('exact', var)], key=lambda x: x[0])
        out += f" | {best[0]:.3f} ({best[0] / vox:.2f}x), {' + '.join(best[1][:3])}"
    print(out + " |")
