# On the device: the FID Inception and ST-LPIPS weights `make setup` made here, in three calls (the FID file is
# 96 MB; a call carries about 49 MB beside the tree). Staged, git-ignored: .bench/fid1 (fid.pth.part00 and
# alex_shift_tolerant.pth, 42 MB), .bench/fid2 (part01), .bench/fid3 (part02, weights.sha256); `split -b 32M -d`.
#   calls 1-3 (carry .bench/fidN):  bash docs/benchmarks/ray/weights.sh
# Then SPLATFILL_WEIGHTS=/tmp/weights fills the FID, KID and ST-LPIPS columns there.
W=/tmp/weights; mkdir -p $W
cp .bench/*/fid.pth.part0* .bench/*/alex_shift_tolerant.pth .bench/*/weights.sha256 $W/ 2>/dev/null  # from whichever carried folder holds them
if [ -f $W/fid.pth.part00 ] && [ -f $W/fid.pth.part01 ] && [ -f $W/fid.pth.part02 ]; then
  cat $W/fid.pth.part0[012] > $W/fid.tmp && mv $W/fid.tmp $W/fid_inception_fid_helper.pth && rm $W/fid.pth.part0*  # whole or absent: cells may be reading
  (cd $W && sha256sum -c weights.sha256) || exit 1
else
  ls $W
fi
