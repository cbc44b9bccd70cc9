# the jobs of the device runners (run9/runner.sh, run10/runner.sh), sourced by them: one scene's base run (train,
# remove, holes, each timed into the benchmark's stage_times.json so scripts/benchmark.py resumes from them) and its
# completions (the cells in $METHODS, Init and Ref unless given, with the inpainters in $INPAINTERS, $COMPLETE_STEPS
# steps, 10k unless given; FT's perceptual term $PERCEPTUAL, l1 unless given: st-lpips needs the weights staged by
# docs/benchmarks/ray/weights.sh and SPLATFILL_WEIGHTS=/tmp/weights); a worker's $GPU, where set, tags its lines.
# A scene named <scene>_b<N> (a link to <scene>, docs/benchmarks/budget/curve.sh) trains with --max-gaussians N.
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1 SPLATFILL_ENGINE_PYTHON=$(command -v python3)
B=/tmp/b; W=$B/out/work
stage() {  # key, done path, times file, engine args...
  local key=$1 done=$2 times=$3 name=$(basename $(dirname $(dirname $3))); shift 3
  [ -e $done ] && return 0
  local t0=$(date +%s.%N)
  python3 -m engine "$@" > $B/log_${name}_$key.txt 2>&1 || { echo "$(date +%T) FAILED $name $key"; return 1; }
  python3 -c "import json,sys,os; p=sys.argv[1]; d=json.load(open(p)) if os.path.exists(p) else {}; d[sys.argv[2]]=round($(date +%s.%N)-$t0,1); json.dump(d,open(p,'w'),indent=1)" $times $key
  echo "$(date +%T) ${GPU:+gpu$GPU }$name $key done"
}
base() {
  local s=$1 R=$W/$1/seed0/run T=$W/$1/seed0/stage_times.json; mkdir -p $W/$s/seed0
  local obj=$(python3 -c "import json; from engine.formats.layout import SceneLayout as L; print([o['name'] for o in json.load(open(L('$B/scenes/$s').objects_json)) if o.get('target')][0])")
  local budget=""; [[ $s =~ _b([0-9]+)$ ]] && budget="--max-gaussians ${BASH_REMATCH[1]}"  # budget/curve.sh's names
  stage train $R/point_cloud.ply $T train --scene $B/scenes/$s --out $R --seed 0 --preset default --device cuda $budget &&
  stage remove $R/removed $T remove --run $R --object $obj --device cuda &&
  stage holes $R/holes $T holes --run $R --device cuda && touch $W/$s/.base || touch $W/$s/.failed
}
complete() {
  python3 scripts/benchmark.py --scenes $B/scenes/$1 --methods ${METHODS:-init reference} --inpainters ${INPAINTERS:-exemplar} --seeds 0 \
    --out $B/out --complete-steps ${COMPLETE_STEPS:-10000} --perceptual ${PERCEPTUAL:-l1} --device cuda > $B/bench_$1.log 2>&1
  echo "$(date +%T) ${GPU:+gpu$GPU }$1 completions done: $(grep -c '\] ' $B/bench_$1.log) cells"; touch $W/$1/.complete
}
