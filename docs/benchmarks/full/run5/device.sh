# Run 5 of the full table (issues 16, 17, 18): livingroom_s0 and tabletop_s0 at today's code (the other objects' own
# shadows left dark, b7e1bd0..dfe43b7; exemplar's views in threads on the GPU where `threads` measured it faster),
# the benchmark's training seeds 0 and 1, on four GPUs: each (scene, seed) is one serial benchmark process pinned to
# its own GPU, as in run 4 (../run4/device.sh says why serial), so each process's wall time is also one scene's whole
# matrix on one GPU.
# The tree travels without docs' pictures (a sparse checkout here: 4.5 MiB instead of 30.6), so a call carries about
# 59 MiB beside it:
#   call 1 carry .whl .bench/full_1 .bench/full_3   `device.sh recv && device.sh threads`  (gsplat builds behind)
#   call 2 carry .bench/full_2 .bench/fid1          `device.sh recv && device.sh start`
#   call 3 carry .bench/fid2 .bench/fid3            `device.sh recv`
#   call 4 carry .bench/fid4 .bench/ff              `device.sh recv && device.sh wait 480`
#   then `device.sh wait N`, `device.sh collect 0 0`, `device.sh collect 1 0`
# What ran was a copy of run 4's script with these changes; they are now this wrapper around it (the same steps).
export CHAINS=${CHAINS:-"livingroom_s0:0 livingroom_s0:1 tabletop_s0:0 tabletop_s0:1"}  # (scene:seed) one per GPU
RUN4=docs/benchmarks/full/run4/device.sh
case $1 in
threads)  # exemplar on the GPU: one view at a time against eight in threads (docs/benchmarks/inpaint/threads.py)
  PYTHONPATH=/tmp/site:. CUDA_VISIBLE_DEVICES=3 python3 docs/benchmarks/inpaint/threads.py 16 1 8 2>&1 | tee $OUT/threads.txt;;
start)  # the code as of this call (recv copied the first call's, to build gsplat from), once the build is done
  for k in $(seq 60); do grep -q built /tmp/b/gsplat.log 2>/dev/null && break; sleep 5; done
  rm -rf /tmp/b/code && cp -r . /tmp/b/code && bash $RUN4 start;;
*) bash $RUN4 "$@";;
esac
