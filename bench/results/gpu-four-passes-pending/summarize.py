# Prints docs/benchmarks.md's table from a run of run.sh: the faster of two
# rounds; voxels and exact from both builds, exact times the same build's
# voxels, with its passes (voxel pass + check + refinement; after, the
# refinement includes the finishing pass).
import os, sys
sys.path.insert(0, os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
import gpu_bench_runs
rows = gpu_bench_runs.read(sys.argv[1])
builds = ('before', 'after')
print('| scene | feature size | size | voxels before | voxels after | exact before | exact after |')
print('|---' * 7 + '|')
for k, v in rows.items():
    vox = {b: min(x[0] for x in v[('voxels', b)]) for b in builds}
    out = f"| {k[0]} | {k[1]} | {k[2]} | {vox['before']:.3f} | {vox['after']:.3f}"
    for b in builds:
        e = min(v[('exact', b)], key=lambda x: x[0])
        out += f" | {e[0]:.3f} ({e[0] / vox[b]:.2f}x), {' + '.join(e[1][:3])}"
    print(out + ' |')
