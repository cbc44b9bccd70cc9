# wait for a detached job's log to say "done" (or the time to run out), then copy its results to $OUT
log=$1; limit=$2; end=$(( $(date +%s) + limit ))
while ! grep -q "^done" $log 2>/dev/null && [ $(date +%s) -lt $end ]; do sleep 5; done
cat $log; cp /tmp/r/out/* $OUT/ 2>/dev/null; ls -la $OUT
