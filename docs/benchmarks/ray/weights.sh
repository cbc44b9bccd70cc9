# On the device: the FID Inception and ST-LPIPS weights `make setup` made here, in two calls (the FID file is
# 96 MB, over what one call carries). Staged, git-ignored: .bench/fid1 (fid.pth.part00), .bench/fid2
# (fid.pth.part01, alex_shift_tolerant.pth, weights.sha256); made with `split -b 48M -d`.
#   call 1 (carry .bench/fid1), call 2 (carry .bench/fid2):  bash docs/benchmarks/ray/weights.sh
# Then SPLATFILL_WEIGHTS=/tmp/weights fills the FID, KID and ST-LPIPS columns there.
W=/tmp/weights; mkdir -p $W
cp .bench/fid1/* $W/ 2>/dev/null; cp .bench/fid2/* $W/ 2>/dev/null
if [ -f $W/fid.pth.part00 ] && [ -f $W/fid.pth.part01 ]; then
  cat $W/fid.pth.part00 $W/fid.pth.part01 > $W/fid_inception_fid_helper.pth && rm $W/fid.pth.part0*
  (cd $W && sha256sum -c weights.sha256) || exit 1
else
  ls $W
fi
