# Prints the tables of docs/benchmarks.md from a run of run.sh: the faster of two rounds.
# Voxels before and after; exact before, then the after build with the list's order
# at each KERF_EXPERIMENT_LONG (0: the order listed), as ms, times the after voxels,
# and the refinement's pass.
import os, sys
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import gpu_bench_runs
rows = gpu_bench_runs.read(sys.argv[1])
variants = ['before', '0', '2', '4', '8']
print('| scene | feature size | size | voxels before | voxels after | ' + ' | '.join(f'exact {v}' for v in variants) + ' |')
print('|---' * (5 + len(variants)) + '|')
for key, v in rows.items():
    vb = min(x[0] for x in v[('voxels', 'before')])
    va = min(x[0] for x in v[('voxels', 'after')])
    out = f"| {key[0]} | {key[1]} | {key[2]} | {vb:.3f} | {va:.3f}"
    for var in variants:
        if ('exact', var) not in v:
            out += ' | -'
            continue
        best = min(v[('exact', var)], key=lambda x: x[0])
        out += f" | {best[0]:.3f} ({best[0] / va:.2f}x), r {best[1][2]}"
    print(out + " |")
