# on the device, detached: whenever a scene has been unpacked, train it, remove its target and mask its holes
# (timed into the benchmark's stage_times.json, so scripts/benchmark.py resumes from them); in the time
# between, the completions (Init and Ref with the inpainters in $INPAINTERS, 10k steps) of the scenes named in
# $COMPLETE that are done, in the order given (ninth trainings: the base runs first, then Init against Ref)
source "$(dirname "$0")/jobs.sh"
while true; do
  next=""
  for s in "$@"; do [ -e $B/scenes/$s/.ready ] && [ ! -e $W/$s/.base ] && { next="base $s"; break; }; done
  [ -z "$next" ] && for s in $COMPLETE; do [ -e $W/$s/.base ] && [ ! -e $W/$s/.complete ] && { next="complete $s"; break; }; done
  [ -z "$next" ] && { n=0; for s in "$@"; do { [ -e $W/$s/.complete ] || { [ -e $W/$s/.base ] && [[ " $COMPLETE " != *" $s "* ]]; }; } && n=$((n+1)); done; [ $n = $# ] && break; sleep 5; continue; }
  $next
done
echo "$(date +%T) all done"
