# Carry what a call cannot: the tree is now 25.7 MB, so Ray's and the FID weights' 41-43 MB folders no longer fit
# beside it in a call's 64 MiB (run 3 was refused). Here: `bash chunks.sh pack NAME DIR...` tars the DIRs (paths
# under .bench) into .bench/ch_NAME_<k>/NAME.tar.<k>of3, three parts of at most 36 MB. On the device, each call
# carrying one part runs `bash docs/benchmarks/full/chunks.sh recv`: it keeps the parts in /tmp/chunks and, once
# a tar has all three, unpacks it into the tree's .bench (the carried paths come back as they were here), after
# which recv.sh takes them as if carried. Run 3: `pack t1 .bench/full_lr1 .bench/ray1 .bench/ray2` (livingroom's
# first part, Ray) then `pack t2 .bench/fid1 .bench/fid2 .bench/fid3`, six calls in all.
if [ "$1" = pack ]; then
  name=$2; shift 2; tar cf .bench/$name.tar "$@" && split -n 3 -d .bench/$name.tar .bench/$name.tar. || exit 1
  for k in 0 1 2; do mkdir -p .bench/ch_${name}_$k; mv .bench/$name.tar.0$k .bench/ch_${name}_$k/$name.tar.$((k+1))of3; done
  rm .bench/$name.tar; du -sh .bench/ch_${name}_*
elif [ "$1" = recv ]; then
  mkdir -p /tmp/chunks; cp .bench/ch_*/*.tar.*of3 /tmp/chunks/ 2>/dev/null
  for part in /tmp/chunks/*.tar.1of3; do name=$(basename $part .tar.1of3)
    [ -f /tmp/chunks/$name.tar.2of3 ] && [ -f /tmp/chunks/$name.tar.3of3 ] || continue
    cat /tmp/chunks/$name.tar.{1,2,3}of3 | tar x -C . && rm /tmp/chunks/$name.tar.* && echo "unpacked $name"
  done; ls /tmp/chunks
fi
