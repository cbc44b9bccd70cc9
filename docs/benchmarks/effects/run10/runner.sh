# on the device, detached: one worker per GPU (run9/runner.sh's jobs, spread): whenever a scene has been unpacked, a
# free GPU trains it, removes its target and masks its holes; in the time between, the completions (Init and Ref with
# the inpainters in $INPAINTERS, 10k steps) of the scenes named in $COMPLETE whose base runs are done. A job is
# claimed by making its folder under $W/.claims (atomic), so two workers never take the same one.
export PYTHONPATH=/tmp/site:. PYTHONUNBUFFERED=1 SPLATFILL_ENGINE_PYTHON=$(command -v python3)
B=/tmp/b; W=$B/out/work; mkdir -p $W/.claims
stage() {  # key, done path, times file, engine args...
  local key=$1 done=$2 times=$3 name=$(basename $(dirname $(dirname $3))); shift 3
  [ -e $done ] && return 0
  local t0=$(date +%s.%N)
  python3 -m engine "$@" > $B/log_${name}_$key.txt 2>&1 || { echo "$(date +%T) FAILED $name $key"; return 1; }
  python3 -c "import json,sys,os; p=sys.argv[1]; d=json.load(open(p)) if os.path.exists(p) else {}; d[sys.argv[2]]=round($(date +%s.%N)-$t0,1); json.dump(d,open(p,'w'),indent=1)" $times $key
  echo "$(date +%T) gpu$GPU $name $key done"
}
base() {
  local s=$1 R=$W/$1/seed0/run T=$W/$1/seed0/stage_times.json; mkdir -p $W/$s/seed0
  local obj=$(python3 -c "import json; from engine.formats.layout import SceneLayout as L; print([o['name'] for o in json.load(open(L('$B/scenes/$s').objects_json)) if o.get('target')][0])")
  stage train $R/point_cloud.ply $T train --scene $B/scenes/$s --out $R --seed 0 --preset default --device cuda &&
  stage remove $R/removed $T remove --run $R --object $obj --device cuda &&
  stage holes $R/holes $T holes --run $R --device cuda
  touch $W/$s/.base
}
complete() {
  python3 scripts/benchmark.py --scenes $B/scenes/$1 --methods init reference --inpainters ${INPAINTERS:-exemplar} --seeds 0 \
    --out $B/out --complete-steps 10000 --perceptual l1 --device cuda > $B/bench_$1.log 2>&1
  echo "$(date +%T) gpu$GPU $1 completions done: $(grep -c '\] ' $B/bench_$1.log) cells"; touch $W/$1/.complete
}
claim() { mkdir $W/.claims/$1 2>/dev/null; }
worker() {
  export GPU=$1 CUDA_VISIBLE_DEVICES=$1; shift
  while true; do
    next=""
    for s in "$@"; do [ -e $B/scenes/$s/.ready ] && claim base_$s && { next="base $s"; break; }; done
    [ -z "$next" ] && for s in $COMPLETE; do [ -e $W/$s/.base ] && claim complete_$s && { next="complete $s"; break; }; done
    if [ -z "$next" ]; then  # finished when every scene's base run (and, where asked, its completions) is claimed and done
      n=0; for s in "$@"; do { [ -e $W/$s/.complete ] || { [ -e $W/$s/.base ] && [[ " $COMPLETE " != *" $s "* ]]; }; } && n=$((n+1)); done
      [ $n = $# ] && break; sleep 5; continue
    fi
    $next
  done
  echo "$(date +%T) gpu$GPU done"
}
gpus=$(nvidia-smi -L | wc -l)
for g in $(seq 0 $((gpus - 1))); do worker $g "$@" > $B/runner_gpu$g.log 2>&1 & done
wait
echo "$(date +%T) all done ($gpus GPUs)"
