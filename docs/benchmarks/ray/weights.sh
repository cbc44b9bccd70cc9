# On the device: the FID Inception and ST-LPIPS weights `make setup` made here, in several calls (the FID file is
# 96 MB; with the tree at 30.6 MiB a call carries about 33 MiB beside it). Staged, git-ignored: .bench/fid1..fid4,
# made by `bash docs/benchmarks/ray/weights.sh split` here: fid.pth.part00-03 (`split -b 24M -d`), fid.pth.parts
# (how many: with the first part, so that no call joins too few), alex_shift_tolerant.pth and weights.sha256 with
# the last part.
#   each call (carry .bench/fidN):  bash docs/benchmarks/ray/weights.sh
# Then SPLATFILL_WEIGHTS=/tmp/weights fills the FID, KID and ST-LPIPS columns there.
if [ "$1" = split ]; then  # here, from the repository root
  rm -rf .bench/fid[0-9] .bench/fidtmp && mkdir -p .bench/fidtmp && cd .bench/fidtmp || exit 1
  split -b 24M -d ../../.weights/fid_inception_fid_helper.pth fid.pth.part && n=$(ls fid.pth.part* | wc -l) && echo $n > fid.pth.parts
  (cd ../../.weights && sha256sum fid_inception_fid_helper.pth alex_shift_tolerant.pth) > weights.sha256
  k=0; for p in fid.pth.part0*; do k=$((k + 1)); mkdir -p ../fid$k; mv $p ../fid$k/; done
  mv fid.pth.parts ../fid1/ && mv weights.sha256 ../fid$k/ && cp ../../.weights/alex_shift_tolerant.pth ../fid$k/ && cd .. && rmdir fidtmp
  du -sh fid[0-9]; exit 0
fi
W=/tmp/weights; mkdir -p $W
cp .bench/*/fid.pth.part0* .bench/*/fid.pth.parts .bench/*/alex_shift_tolerant.pth .bench/*/weights.sha256 $W/ 2>/dev/null  # from whichever carried folder holds them
n=$(cat $W/fid.pth.parts 2>/dev/null || echo 3)  # (runs before run 5: three parts, no count)
if [ $(ls $W/fid.pth.part0* 2>/dev/null | wc -l) -ge $n ]; then
  cat $W/fid.pth.part0* > $W/fid.tmp && mv $W/fid.tmp $W/fid_inception_fid_helper.pth && rm $W/fid.pth.part0*  # whole or absent: cells may be reading
  (cd $W && sha256sum -c weights.sha256) || exit 1
else
  ls $W
fi
