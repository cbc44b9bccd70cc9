#!/bin/bash
# One runner for every GPU measurement docs/BENCHMARKS.md quotes. Run from the repository root on the GPU machine
# (any Linux host with CUDA and Python 3.12; what it lacks is sent with the tree, below):
#
#   SPLATFILL_COMMIT=<commit here> bash benchmarks/gpu.sh NAME [ARGS...]
#
# Every job first takes what was sent with the tree, once per machine (a fresh machine is bare):
#   .whl/*.whl              wheels (gsplat, plyfile, lpips, ...) into /tmp/site
#   .gsplat_build/*.tgz     gsplat's CUDA extension built on an earlier machine (`save-build` makes it); else it is
#                           built once here (about 80 s), before any clock starts
#   .bench/*/*.tgz.KofN     generated scenes packed by benchmarks/pack_scene.py -> /tmp/gpu/scenes/<name>
#   .bench/carry-*/         large files split by benchmarks/carry.py -> /tmp/gpu/files (wheels there installed,
#                           weights there used as SPLATFILL_WEIGHTS)
# A SCENE argument is a name under /tmp/gpu/scenes or a path. Records go to $OUT/NAME/ (the folder the host's
# results are fetched from), or to RESULTS=DIR. SPLATFILL_COMMIT names the code where the tree has no .git.
#
# NAMEs (each a measurement of one BENCHMARKS section; a variant to judge is a branch or an engine flag, never a patch):
#   setup                          only the above
#   train SCENE... [--budgets N..] benchmarks/train_speed.py: training time, test PSNR, memory      ("Training")
#   profile SCENE [ARGS]           benchmarks/train_profile.py: where a step's time goes             ("Training")
#   render SCENE [ARGS]            benchmarks/render_speed.py: one render forward + backward         ("Training")
#   rasterizer SCENE               benchmarks/rasterizer_agreement.py: reference rasterizer vs gsplat ("CPU facts")
#   metrics                        benchmarks/metrics_agreement.py: LPIPS and FID vs their packages  ("CPU facts")
#   removal SCENE                  benchmarks/removal_sweep.py: thresholds and hole-mask settings     ("Removal")
#   segments SCENE...              a 100k-budget training each, then benchmarks/segments.py    ("Objects without masks")
#   capture PHOTOS...              benchmarks/capture_path.py: the README's "Your own capture" on real photos, timed, and
#                                  its pictures, then what its subject was chosen from (subject_inputs.py, after the
#                                  timed path: the statue's base plate stayed at 748ee7a, to study here); with
#                                  FLOATERS=1 then benchmarks/floaters.py on its trained run (what covers its worst
#                                  test views; the PSNRs without each candidate rule's Gaussians: judged at 557c660,
#                                  neither rule kept, so off unless asked)                              ("Real captures")
#   inpaint PHOTOS [VIEWS]         benchmarks/inpaint_speed.py: seconds per 1 MP view, every offline inpainter ("Inpainting")
#   subject SCENE...               train, segment --auto (scored by benchmarks/segments.py), remove object_1, holes:
#                                  the subject found and removed without masks, and what it was chosen from
#                                  (benchmarks/subject_inputs.py: an npz that collect brings back for
#                                  benchmarks/subject_sweep.py here)                            ("Objects without masks")
#   trained SCENE...               `engine train` at the defaults with TRAIN_FLAGS added, each scene's metrics.json
#                                  (test PSNR, seconds) named by the flags: a training setting judged   ("Training")
#   subject-inputs PHOTOS...       the README's capture, train (TRAIN_FLAGS added) and segment --auto on real photos,
#                                  then benchmarks/subject_inputs.py: what the subject was chosen from, an npz to study here
#   judge SCENE [REMOVE FLAGS]     base run, remove (with the flags), holes and a variant of them (JUDGE_VARIANT),
#                                  each inpainted (JUDGE_INPAINTER) and completed by Ref; scored by removal_score.py,
#                                  ring_colour.py, hole_error.py and leftovers.py            ("Removal and its effects")
#   judge-pair SCENE FLAGS         judge at the defaults, then with the remove FLAGS on the same base run (records
#                                  of the second under judge_flags/): a removal flag judged against the default
#   matrix SCENE... [-- ARGS]      benchmarks/matrix.py's whole matrix (its own defaults, ARGS added)   ("Completion")
#   heldout SCENE... [-- ARGS]     the held-out table: one matrix process per scene, two a GPU (HELDOUT_CELLS's cells,
#                                  ARGS added), then their tables merged into $OUT/heldout/       ("Held-out table")
#   seeds SCENE... [-- ARGS]       one scene's cells at several training seeds (SEEDS, default 0 1 2), one matrix process
#                                  a (scene, seed), all at once (SEEDS_CELLS: Ref-coherence, the default): how far a
#                                  scene's numbers move from run to run, with each run's sheets     ("Held-out table")
#   start NAME [ARGS]              any of the above detached (for runs past one call's 10 minutes); its records go
#                                  to /tmp/gpu/out/NAME, its log to /tmp/gpu/NAME.log
#   wait SECONDS                   until the detached runs end or SECONDS pass; when they have, `collect` too (one
#                                  session lost every record twice: the machine went before the call after `wait`)
#   collect                        the detached runs' records (JSON, CSV, Markdown, text, pictures as JPEGs) as one file,
#                                  $OUT/records.tgz, to fetch at once, and their npz arrays beside it (seven at most)
#   save-build                     gsplat's built extension into $OUT/gsplat_build.tgz (send it back as .gsplat_build/)
#   wheels                         HERE, not on the GPU machine: download the wheels it lacks into .whl/ (17 MB,
#                                  git-ignored); imageio-ffmpeg (68 MB, for turntable MP4s) goes through carry.py
#   pack                           HERE: `wheels`, then what the real captures need in three sends of under 64 MiB:
#                                  .bench/carry-1 (pycolmap, lpips, onnxruntime's small deps), .bench/carry-2
#                                  (onnxruntime, the u2netp and ST-LPIPS weights from `make setup`), .bench/cap/skull
#                                  and .bench/cap_statue_only/statue (the photos): send [.whl, .bench/carry-1] with
#                                  `setup`, [.bench/carry-2, .bench/cap], then [.bench/cap_statue_only]
set -o pipefail
if [ "$1" = wheels ]; then
  python3 -m pip download -q --no-deps --only-binary=:all: --python-version 3.12 --implementation cp \
    --platform manylinux_2_28_x86_64 --platform manylinux_2_27_x86_64 --platform manylinux_2_17_x86_64 \
    --platform manylinux2014_x86_64 -d .whl gsplat==1.5.3 jaxtyping wadler-lindig plyfile==1.1.5 OpenImageIO==3.2.2.0 \
    rich markdown-it-py mdurl pygments && du -sh .whl; exit; fi
if [ "$1" = pack ]; then
  bash "$0" wheels || exit 1
  [ -f .weights/u2netp.onnx ] && [ -f .weights/alex_shift_tolerant.pth ] || { echo "gpu.sh pack: run make setup first" >&2; exit 1; }
  big=$(mktemp -d); python3 -m pip download -q --no-deps --only-binary=:all: --python-version 3.12 --implementation cp \
    --platform manylinux_2_28_x86_64 --platform manylinux2014_x86_64 -d $big pycolmap==4.2.1 onnxruntime==1.31.1 \
    lpips==0.1.4 coloredlogs==15.0.1 flatbuffers humanfriendly==10.0 || exit 1
  rm -rf .bench/carry-*; python3 benchmarks/carry.py split $big/pycolmap-*.whl $big/coloredlogs-*.whl $big/flatbuffers-*.whl \
    $big/humanfriendly-*.whl $big/lpips-*.whl $big/onnxruntime-*.whl .weights/alex_shift_tolerant.pth .weights/u2netp.onnx --mb 40
  photos=${CAPTURES:-../shared/captures}; rm -rf .bench/cap .bench/cap_statue_only
  mkdir -p .bench/cap/skull .bench/cap_statue_only/statue && cp -r $photos/skull/images .bench/cap/skull/ &&
    cp -r $photos/statue/images .bench/cap_statue_only/statue/ && du -sh .whl .bench/*; rm -rf $big; exit; fi
G=/tmp/gpu; mkdir -p $G/scenes $G/files $G/out
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1 SPLATFILL_ENGINE_PYTHON=$(command -v python3)
export SPLATFILL_WEIGHTS=${SPLATFILL_WEIGHTS:-$G/files} TORCH_CUDA_ARCH_LIST=${TORCH_CUDA_ARCH_LIST:-9.0}
EXT=${TORCH_EXTENSIONS_DIR:-/root/.cache/torch_extensions/py312_cu130}
[ -n "$SPLATFILL_COMMIT" ] || echo "gpu.sh: SPLATFILL_COMMIT is not set: records will name no commit" >&2
GPUS=$(nvidia-smi -L 2>/dev/null | wc -l); [ "$GPUS" -gt 0 ] || { echo "gpu.sh: no GPU on this machine" >&2; exit 2; }
export OMP_NUM_THREADS=${OMP_NUM_THREADS:-$(( $(nproc) / GPUS ))}  # processes a GPU each must not spin on all cores
# the held-out table's cells: the four methods with telea and the default inpainter (docs/BENCHMARKS.md)
HELDOUT_CELLS=${HELDOUT_CELLS:---seeds 0 --methods init reference ft3 direct --inpainters telea coherence}

setup() {
  python3 benchmarks/carry.py join $G/files
  local wheels=() w  # each wheel once per machine: a wheel whose parts all came later is installed then
  for w in $(ls .whl/*.whl $G/files/*.whl 2>/dev/null); do [ -f $G/.installed.$(basename $w) ] || wheels+=($w); done
  if [ ${#wheels[@]} -gt 0 ]; then
    python3 -m pip install -q --no-index --no-deps --no-compile --no-cache-dir --upgrade --target /tmp/site "${wheels[@]}" &&
      for w in "${wheels[@]}"; do touch $G/.installed.$(basename $w); done || exit 1
  fi
  ls .bench/*/*.tgz.*of* > /dev/null 2>&1 && { mkdir -p $G/parts; cp .bench/*/*.tgz.*of* $G/parts/; }
  [ -d $G/parts ] && python3 benchmarks/unpack_scene.py $G/parts $G/scenes
  if [ ! -d $EXT/gsplat_cuda ] && ls .gsplat_build/*.tgz > /dev/null 2>&1; then
    # ninja rebuilds an object whose logged mtime is older than a source's: date back the sources pip just wrote
    mkdir -p $EXT && tar xzf .gsplat_build/*.tgz -C $EXT && find /tmp/site/gsplat -type f -exec touch -d 2020-01-01 {} +
  fi
  [ -f $G/.built ] || { python3 -c "from engine.render.rasterize import gsplat_rasterization as g; g()" > $G/build.log 2>&1 &&
    touch $G/.built || { tail -5 $G/build.log; exit 1; }; }
}

scene() { [ -d "$1" ] && echo "$1" || echo $G/scenes/$1; }
flags_tag() { [ -z "$TRAIN_FLAGS" ] || echo _$(echo "$TRAIN_FLAGS" | tr -c 'A-Za-z0-9' '_' | tr -s _ | sed 's/^_//; s/_$//'); }
out() { local d=${RESULTS:-${OUT:-$G/out}}/$1; mkdir -p $d; echo $d; }

judge() {  # $1 scene, the rest flags for `engine remove`; JUDGE_INPAINTER (telea), and a second set of hole masks
  # made with JUDGE_VARIANT's `holes` flags (unset: --no-see-through; empty: the same masks; none: no second set, for
  # half the device time) inpainted with JUDGE_DILATE's `inpaint --dilate` (0), each inpainted and completed with Ref
  local S=$(scene $1) J=$G/judge/$1 D=$(out judge${JUDGE_TAG:+_$JUDGE_TAG}) I=${JUDGE_INPAINTER:-telea}
  local V=${JUDGE_VARIANT---no-see-through}
  local W=${JUDGE_DILATE:-0}
  shift; mkdir -p $J
  local target=$(python3 -c "import json,sys; print(next(o['name'] for o in json.load(open(sys.argv[1])) if o.get('target')))" $S/masks/objects.json)
  [ -f $J/run/point_cloud.ply ] || python3 -m engine train --scene $S --out $J/run --device cuda > $J/train.log 2>&1 || { tail -5 $J/train.log; return 1; }
  rm -rf $J/run/removed $J/run/holes* $J/run/inpainted* $J/run/complete*
  local name=$(basename $S) R=$J/run
  { python3 -m engine remove --run $R --object "$target" --device cuda "$@" && python3 -m engine holes --run $R &&
    python3 -m engine inpaint --run $R --inpainter $I &&
    python3 -m engine complete --run $R --method reference --inpainter $I --device cuda &&
    { [ "$V" = none ] || { python3 -m engine holes --run $R --out $R/holes_variant $V &&
    python3 -m engine inpaint --run $R --inpainter $I --holes $R/holes_variant --out $R/inpainted_variant --dilate $W &&
    python3 -m engine complete --run $R --method reference --inpainter $I --device cuda --inpainted $R/inpainted_variant \
      --out $R/complete_variant; }; }; } > $J/chain.log 2>&1 || { tail -5 $J/chain.log; return 1; }
  local ref=$(ls -d $R/complete/Ref-*) var=$R/complete_variant variant=()
  [ "$V" = none ] || variant=("Ref-$I-variant=$var/renders")
  python3 benchmarks/removal_score.py $S $R/removed --picture $D/${name}_judge.jpg > $D/${name}_judge.txt
  python3 benchmarks/ring_colour.py $R $S >> $D/${name}_judge.txt  # the patch's colour against the truth's ring
  python3 benchmarks/hole_error.py $S removed=$R/removed/images "Ref-$I=$ref/renders" "${variant[@]}" \
    --picture $D/${name}_hole_crops.png > $D/${name}_hole_error.txt
  cp $R/metrics.json $D/${name}_base_metrics.json; cp $R/removed/removal.json $D/${name}_removal.json
  cp $R/holes/holes.json $D/${name}_holes.json
  cp $R/removed/sheet.png $D/${name}_removed_sheet.png; cp $R/holes/sheet.png $D/${name}_holes_sheet.png
  cp $ref/scores.json $D/${name}_ref_scores.json
  cp $R/inpainted/$I/config.json $D/${name}_inpaint.json; cp $R/inpainted/$I/sheet_test.png $D/${name}_inpainted.png
  [ "$V" = none ] || { cp $R/holes_variant/holes.json $D/${name}_holes_variant.json
    cp $var/scores.json $D/${name}_ref_variant_scores.json; cp $R/inpainted_variant/config.json $D/${name}_inpaint_variant.json
    cp $R/inpainted_variant/sheet_test.png $D/${name}_inpainted_variant.png; }
  python3 benchmarks/leftovers.py $R $D/${name}_leftovers.json; cat $D/${name}_judge.txt $D/${name}_hole_error.txt
}

name=$1; shift
[ "$name" = wait ] || [ "$name" = collect ] || setup
case $name in
  setup) ls $G/scenes $G/files; python3 -c "import gsplat, torch; print('gsplat', gsplat.__version__, torch.cuda.get_device_name())";;
  train) s=(); while [ $# -gt 0 ] && [ "${1#--}" = "$1" ]; do s+=("$(scene $1)"); shift; done
         python3 benchmarks/train_speed.py --scenes "${s[@]}" --results $(out train) "$@";;
  profile) python3 benchmarks/train_profile.py --scene $(scene $1) --json $(out profile)/$1.json "${@:2}";;
  render) python3 benchmarks/render_speed.py --scene $(scene $1) "${@:2}" | tee $(out render)/$1.txt;;
  rasterizer) python3 benchmarks/rasterizer_agreement.py --scene $(scene $1) --out $(out rasterizer)/rasterizer_agreement.json;;
  metrics) python3 benchmarks/metrics_agreement.py --results $(out metrics);;
  removal) python3 benchmarks/removal_sweep.py --scene $(scene $1) --results $(out removal) "${@:2}";;
  segments) runs=(); for s in "$@"; do
              python3 -m engine train --scene $(scene $s) --out $G/seg/$s --max-gaussians 100000 --device cuda > $G/seg_$s.log 2>&1 ||
                { tail -5 $G/seg_$s.log; exit 1; }; runs+=($G/seg/$s); done
            python3 benchmarks/segments.py --run "${runs[@]}" --results $(out segments);;
  judge) judge "$@";;
  judge-pair) judge $1 && JUDGE_TAG=flags judge "$@";;  # same base run: at the defaults, then with the flags
  inpaint) python3 benchmarks/inpaint_speed.py $1 $(out inpaint) ${2:-16};;
  capture) for p in "$@"; do n=$(basename $(dirname $p)); [ "$(basename $p)" = images ] || n=$(basename $p)
             rm -rf $G/cap/$n; python3 benchmarks/capture_path.py $p $G/cap/$n $(out capture) &&
               python3 benchmarks/subject_inputs.py $G/cap/$n/run $(out capture)/${n}_subject_inputs.npz --device cuda &&
               { [ "$FLOATERS" != 1 ] ||
             python3 benchmarks/floaters.py $G/cap/$n/run $(out capture)/${n}_floaters.json --device cuda | tail -n 14; }; done;;
  subject) for s in "$@"; do S=$(scene $s) R=$G/subject/$s D=$(out subject); rm -rf $R
             { python3 -m engine train --scene $S --out $R --device cuda && python3 -m engine segment --run $R --auto &&
               python3 benchmarks/segments.py --run $R --results $D --from-run &&
               python3 benchmarks/subject_inputs.py $R $D/${s}_inputs.npz --device cuda &&
               python3 -m engine remove --run $R --object object_1 &&
               python3 -m engine holes --run $R; } > $G/subject_$s.log 2>&1 || { tail -5 $G/subject_$s.log; continue; }
             cp $R/removed/removal.json $D/${s}_removal.json; cp $R/holes/holes.json $D/${s}_holes.json
             cp $R/segments/sheet.png $D/${s}_segments.png; python3 -c "import json,sys; r=json.load(open(sys.argv[1])); h=json.load(open(sys.argv[2])); print(sys.argv[3], 'removed', r['removed'], 'psnr outside true hole', r['psnr_outside_hole'], 'hole IoU', h['mean_iou_vs_truth'], 'unseen IoU', h['mean_unseen_iou_vs_truth'])" $D/${s}_removal.json $D/${s}_holes.json $s; done;;
  trained) for s in "$@"; do n=$(basename $s)$(flags_tag) R=$G/trained/$n; rm -rf $R
             python3 -m engine train --scene $(scene $s) --out $R --device cuda $TRAIN_FLAGS > $G/trained_$n.log 2>&1 ||
               { tail -5 $G/trained_$n.log; continue; }
             cp $R/metrics.json $(out trained)/${n}_metrics.json
             python3 -c "import json,sys; m=json.load(open(sys.argv[1])); print(sys.argv[2], 'test PSNR', m['psnr'], 'train s', m['train_seconds'])" \
               $R/metrics.json $n; done;;
  subject-inputs) for p in "$@"; do n=$(basename $(dirname $p)); [ "$(basename $p)" = images ] || n=$(basename $p)
             n=$n$(flags_tag)
             C=$G/diag/$n D=$(out subject-inputs); rm -rf $C
             { python3 -m engine capture --images $p --out $C/capture && python3 -m engine train --scene $C/capture --out $C/run $TRAIN_FLAGS &&
               python3 -m engine segment --run $C/run --auto &&
               python3 benchmarks/subject_inputs.py $C/run $D/${n}_subject.npz; } > $G/subject_inputs_$n.log 2>&1 ||
               { tail -5 $G/subject_inputs_$n.log; continue; }
             cp $C/run/segments/segments.json $D/${n}_segments.json; cp $C/run/metrics.json $D/${n}_metrics.json
             python3 -c "import cv2,sys; i=cv2.imread(sys.argv[1]); cv2.imwrite(sys.argv[2], cv2.resize(i, (500, round(i.shape[0] * 500 / i.shape[1]))))" \
               $C/run/segments/sheet.png $D/${n}_segments.jpg; tail -n 1 $G/subject_inputs_$n.log; done;;
  matrix) s=(); while [ $# -gt 0 ] && [ "$1" != -- ]; do s+=("$(scene $1)"); shift; done; shift
          d=$(out matrix); python3 scripts/benchmark.py --scenes "${s[@]}" --out $G/matrix --device cuda "$@" 2>&1 | tail -n 30
          cp $G/matrix/*.md $G/matrix/*.csv $G/matrix/*.json $d/ 2>/dev/null; cp $G/matrix/*.png $d/ 2>/dev/null;;
  heldout) s=(); while [ $# -gt 0 ] && [ "$1" != -- ]; do s+=("$1"); shift; done; shift
           d=$(out heldout); i=0; date +%s > $d/start.txt
           export OMP_NUM_THREADS=$(( $(nproc) / ${#s[@]} > 0 ? $(nproc) / ${#s[@]} : 1 ))  # the cores shared out
           for n in "${s[@]}"; do  # scene k on GPU k mod GPUS, all at once
             CUDA_VISIBLE_DEVICES=$(( i % GPUS )) python3 scripts/benchmark.py --scenes $(scene $n) --out $G/heldout/$n \
               --device cuda --scheduler serial $HELDOUT_CELLS "$@" > $G/heldout_$n.log 2>&1 < /dev/null &
             i=$(( i + 1 ))
           done; wait
           for n in "${s[@]}"; do tail -n 1 $G/heldout_$n.log; cp $G/heldout/$n/results.json $d/${n}_results.json
             cp $G/heldout/$n/pictures/$n.png $d/${n}_views.png 2>/dev/null
             w=$G/heldout/$n/work/$n/seed0/run  # the sheets to look at: what removal, holes and the fill did
             cp $w/removed/sheet.png $d/${n}_removed.png 2>/dev/null; cp $w/holes/sheet.png $d/${n}_holes.png 2>/dev/null
             cp $w/holes/holes.json $d/${n}_holes.json 2>/dev/null; cp $w/removed/removal.json $d/${n}_removal.json 2>/dev/null
             cp $w/inpainted/telea/sheet_test.png $d/${n}_inpainted.png 2>/dev/null; done
           cp /tmp/splatfill-error-*.txt $d/ 2> /dev/null  # internal errors' tracebacks, named in the cells' reasons
           python3 benchmarks/heldout_wall.py $d/start.txt $G/heldout $GPUS > $d/wall.json
           python3 benchmarks/merge_tables.py $d $G/heldout/*/results.json &&
             python3 -m engine chart --spec $d/speed_accuracy.json --out $d/speed_accuracy.png; cat $d/wall.json;;
  seeds) s=(); while [ $# -gt 0 ] && [ "$1" != -- ]; do s+=("$1"); shift; done; shift
         d=$(out seeds); i=0
         pairs=$(( ${#s[@]} * $(echo ${SEEDS:-0 1 2} | wc -w) ))  # the cores shared out among them
         export OMP_NUM_THREADS=$(( $(nproc) / pairs > 0 ? $(nproc) / pairs : 1 ))
         for n in "${s[@]}"; do for k in ${SEEDS:-0 1 2}; do  # (scene, seed) pairs spread over the GPUs, all at once
           CUDA_VISIBLE_DEVICES=$(( i % GPUS )) python3 scripts/benchmark.py --scenes $(scene $n) --out $G/seeds/${n}_$k \
             --device cuda --scheduler serial --seeds $k ${SEEDS_CELLS:---methods reference --inpainters coherence} "$@" \
             > $G/seeds_${n}_$k.log 2>&1 < /dev/null &
           i=$(( i + 1 )); done; done; wait
         for n in "${s[@]}"; do for k in ${SEEDS:-0 1 2}; do m=${n}_seed$k w=$G/seeds/${n}_$k/work/$n/seed$k/run
           tail -n 1 $G/seeds_${n}_$k.log; cp $G/seeds/${n}_$k/results.json $d/${m}_results.json
           cp $G/seeds/${n}_$k/pictures/$n.png $d/${m}_views.png 2>/dev/null
           for f in removed/sheet.png holes/sheet.png removed/removal.json holes/holes.json; do
             cp $w/$f $d/${m}_$(echo $f | tr / _) 2>/dev/null; done
           for f in $w/inpainted/*/sheet_test.png $w/complete/*/scores.json; do
             [ -f $f ] && cp $f $d/${m}_$(basename $(dirname $f))_$(basename $f); done
           cp $w/complete/*/scene/reference_fill.json $d/${m}_reference_fill.json 2>/dev/null; done; done;;
  start) tag=$(echo "$*" | tr -c 'A-Za-z0-9_' '_' | cut -c1-40)_$(echo "$* $TRAIN_FLAGS" | md5sum | cut -c1-6)  # one
         # log and pid a job, several at once: the hash of the arguments (and TRAIN_FLAGS) tells apart jobs whose
         # first 40 characters agree
         RESULTS=$G/out setsid nohup bash benchmarks/gpu.sh "$@" > $G/$tag.log 2>&1 < /dev/null &
         echo $! > $G/$tag.pid; sleep 5; tail -n 3 $G/$tag.log;;
  wait) end=$(( $(date +%s) + ${1:-540} ))
        running() { for f in $G/*.pid; do [ -f "$f" ] && kill -0 $(cat $f) 2> /dev/null && return 0; done; return 1; }
        while running && [ $(date +%s) -lt $end ]; do sleep 10; done
        running && echo "still running" || echo "all ended"; tail -n 3 $G/*.log 2>/dev/null
        running || bash "$0" collect;;  # now: a machine lost before the next call (30 s idle) loses nothing
  collect) python3 benchmarks/records.py shrink $G/out  # pictures as JPEGs at most 1600 px wide: a call returns little
           (cd $G/out && find . -type f \( -name '*.json' -o -name '*.csv' -o -name '*.md' -o -name '*.txt' -o -name '*.png' \
             -o -name '*.jpg' \) -size -4M | tar czf $OUT/records.tgz -T -) && tar tzf $OUT/records.tgz | head -40
           find $G/out -name '*.npz' -size -16M | head -n 7 | xargs -r cp -t $OUT/;;  # beside it: arrays to study here
  save-build) tar czf $OUT/gsplat_build.tgz -C $EXT gsplat_cuda && ls -la $OUT;;
  *) awk 'NR > 1 && /^#/ { print; next } NR > 1 { exit }' "$0"; exit 2;;
esac
