# usage: bash components.sh BEFORE_KERF AFTER_KERF  (run from the repository root)
for t in 0.05 0.01; do for f in side-chair stool; do for b in "$1" "$2"; do
$b export resources/examples/$f.kerf -o /tmp/comp.stl --tolerance $t --json 2>/dev/null | python3 -c "
import json,sys; j=json.load(sys.stdin); print('$f $t $b', j['triangles'], 'total %.2f coverage %.2f refine %.2f simplify %.2f lattice %.2f'%(j['seconds'],j['coverage_seconds'],j['refine_seconds'],j['simplify_seconds'],j['lattice_seconds']))"
done; done; done
