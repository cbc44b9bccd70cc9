# On the device: wait up to $1 s for start.sh's benchmark, then pack what has finished (run9/collect.sh does the
# packing; its own wait looks for a runner this chain does not have).
end=$(( $(date +%s) + $1 ))
while pgrep -f "[s]cripts/benchmark.py --scenes" > /dev/null && [ $(date +%s) -lt $end ]; do sleep 10; done
tail -3 /tmp/b/runner.log
SPLATFILL_WEIGHTS=/tmp/weights RUNNER=full-table-has-no-runner bash docs/benchmarks/effects/run9/collect.sh 0
