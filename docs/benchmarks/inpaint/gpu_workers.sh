# On the device, after a full-table run has left its base runs in /tmp/b/out/work (docs/benchmarks/full): exemplar
# on the GPU, one view at a time against 4 and 8 views at once in threads or processes, on one scene's 100
# views; the fills must be identical. Writes
# $OUT/gpu_workers_<source>.txt: each run's inpaint_seconds and whether its images and depth equal the one-view run's.
# (RUN and PY may be given: the CPU check ran it on .bench/tiny/run_m with the engine's venv. SOURCE=input times the
# direct baseline's inpainting of the object's region instead, the 150-159 s one in run 3; WORKERS, default "1 4 8";
# PARALLEL, threads or processes, default the inpainter's own choice: processes on a GPU since session 22.)
export PYTHONPATH=/tmp/site:.; RUN=${RUN:-$(ls -d /tmp/b/out/work/livingroom_s*/seed*/run | head -1)}; PY=${PY:-python3}
W=/tmp/gw; rm -rf $W; mkdir -p $W
for n in ${WORKERS:-1 4 8}; do $PY -m engine inpaint --run $RUN --inpainter exemplar --source ${SOURCE:-removed} --dilate 4 --workers $n ${PARALLEL:+--parallel $PARALLEL} --out $W/w$n > $W/w$n.log 2>&1; done
$PY - $W "${WORKERS:-1 4 8}" > $OUT/gpu_workers_${SOURCE:-removed}${PARALLEL:+_$PARALLEL}.txt <<'PY'
import json, sys, pathlib, numpy as np, cv2
w = pathlib.Path(sys.argv[1])
def files(d): return sorted(p.relative_to(d) for p in d.rglob('*') if p.suffix in ('.png', '.exr') and 'sheet' not in p.name)
base = w / ('w' + sys.argv[2].split()[0])
for n in sys.argv[2].split():
    d = w / f'w{n}'; rep = d / 'config.json'
    same = all(np.array_equal(cv2.imread(str(base / f), cv2.IMREAD_UNCHANGED), cv2.imread(str(d / f), cv2.IMREAD_UNCHANGED)) for f in files(base))
    r = json.loads(rep.read_text()) if rep.is_file() else {}
    print(n, r.get('parallel'), r.get('inpaint_seconds', 'no report'), 'identical' if same else 'DIFFERENT', len(files(d)))
PY
cat $OUT/gpu_workers_${SOURCE:-removed}${PARALLEL:+_$PARALLEL}.txt; nvidia-smi -L | head -1
