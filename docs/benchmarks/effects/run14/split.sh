# on the device, detached, beside run10's runner (run with the same $B): each scene's Init and Ref on GPUs of their
# own instead of one after the other on the GPU that trained it. Claims the scenes' completions from the runner
# (which then only waits), and per scene: once its base run is done, Init on GPU $2+2k (the benchmark's shared
# inpainting stage first), and once that stage is timed in stage_times.json, Ref on the next GPU.
source "$(dirname "$0")/../run9/jobs.sh"
mkdir -p $W/.claims; for s in "$@"; do mkdir -p $W/.claims/complete_$s; done
cell() {  # scene, method, gpu
  CUDA_VISIBLE_DEVICES=$3 python3 scripts/benchmark.py --scenes $B/scenes/$1 --methods $2 --inpainters ${INPAINTERS:-exemplar} \
    --seeds 0 --out $B/out --complete-steps 10000 --perceptual l1 --device cuda > $B/bench_$1_$2.log 2>&1
  echo "$(date +%T) gpu$3 $1 $2 done"
}
one() {  # scene, first gpu
  until [ -e $W/$1/.base ] || [ -e $W/$1/.failed ]; do sleep 5; done; [ -e $W/$1/.failed ] && return
  cell $1 init $2 & 
  until grep -q inpaint- $W/$1/seed0/stage_times.json 2>/dev/null; do sleep 3; done
  cell $1 reference $(($2 + 1)); wait; touch $W/$1/.complete
}
g=0; for s in "$@"; do one $s $g & g=$((g + 2)); done; wait; echo "$(date +%T) split done"
