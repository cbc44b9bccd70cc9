# on the device, detached: one worker per GPU (run9/runner.sh's jobs, spread): whenever a scene has been unpacked, a
# free GPU trains it, removes its target and masks its holes; in the time between, the completions (Init and Ref with
# the inpainters in $INPAINTERS, 10k steps) of the scenes named in $COMPLETE whose base runs are done. A job is
# claimed by making its folder under $W/.claims (atomic), so two workers never take the same one.
source "$(dirname "$0")/../run9/jobs.sh"
mkdir -p $W/.claims
claim() { mkdir $W/.claims/$1 2>/dev/null; }
worker() {
  export GPU=$1 CUDA_VISIBLE_DEVICES=$1; shift
  while true; do
    next=""
    for s in "$@"; do [ -e $B/scenes/$s/.ready ] && claim base_$s && { next="base $s"; break; }; done
    [ -z "$next" ] && for s in $COMPLETE; do [ -e $W/$s/.base ] && claim complete_$s && { next="complete $s"; break; }; done
    if [ -z "$next" ]; then  # finished when every scene's base run (and, where asked, its completions) is claimed and done
      n=0; for s in "$@"; do { [ -e $W/$s/.complete ] || [ -e $W/$s/.failed ] || { [ -e $W/$s/.base ] && [[ " $COMPLETE " != *" $s "* ]]; }; } && n=$((n+1)); done
      [ $n = $# ] && break; sleep 5; continue
    fi
    $next
  done
  echo "$(date +%T) gpu$GPU done"
}
# gsplat's CUDA extension is built once, before the workers: two first uses at once broke each other's build
python3 -c "from engine.render.rasterize import gsplat_rasterization as g; g()" || exit 1
gpus=$(nvidia-smi -L | wc -l)
for g in $(seq 0 $((gpus - 1))); do worker $g "$@" > $B/runner_gpu$g.log 2>&1 & done
wait
echo "$(date +%T) all done ($gpus GPUs)"
