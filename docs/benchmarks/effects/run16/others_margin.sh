# On the device, once livingroom's base run is done (collect.sh shows its removal.json): the removal again with
# around_others.patch (not applied in the tree) at margins OM cells around other objects' bases, each into its own
# folder (after.sh starts it in the background); every removal, today's run's included, scored by run15/breakdown.py
# into $OUT/others_margin.txt (collect.sh packs it too). Issue 16: the orange ring around the sharpener's base.
B=/tmp/b; s=${S:-livingroom_s0}; R=$B/out16_$s/work/$s/seed0/run; C=/tmp/omcode; W=/tmp/om
[ -f $R/removed/removal.json ] || { echo "no base run yet: $R"; exit 1; }
rm -rf $C $W; cp -r $B/code $C; mkdir -p $W
(cd $C && { patch -p1 < docs/benchmarks/effects/run16/around_others.patch || git apply docs/benchmarks/effects/run16/around_others.patch; }) || exit 1
obj=$(python3 -c "import json,sys; print([o['name'] for o in json.load(open(sys.argv[1])) if o.get('target')][0])" $B/scenes/$s/masks/objects.json)
export PYTHONPATH=/tmp/site:$C
{ echo "== today (8356a88: no margin)"; python3 $C/docs/benchmarks/effects/run15/breakdown.py $B/scenes/$s $R/removed
    for m in ${OMS:-0 3 6}; do OM=$m python3 -m engine remove --run $R --object $obj --out $W/om$m --device cuda > $W/om$m.log 2>&1
      echo "== margin $m cells"; python3 $C/docs/benchmarks/effects/run15/breakdown.py $B/scenes/$s $W/om$m
      tail -c 600 $W/om$m.log | grep -i "error" ; done; } > $W/others_margin.txt 2>&1
