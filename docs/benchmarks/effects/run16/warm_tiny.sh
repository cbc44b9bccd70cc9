#!/bin/bash
# (ran from a copy of .bench/tiny/run_lm in /tmp/lmw with `remove --object plush` and `holes` of today's code)
# tiny livingroom (/tmp/lmw: run_lm with today's removal and holes): Init, Ref, Direct from scratch (1,000 steps, a third
# of the base run's, as the benchmark's 10k of 30k) against [warm] at its default (a tenth), exemplar, one thread each
cd /work/main; export PYTHONPATH=. OMP_NUM_THREADS=1 MKL_NUM_THREADS=1
R=/tmp/lmw; E=".venv/bin/python -m engine"
$E inpaint --run $R --inpainter exemplar --dilate 4 --workers 1 > $R.inp.log 2>&1 &
$E inpaint --run $R --inpainter exemplar --source input --dilate 4 --workers 1 > $R.inpd.log 2>&1; wait
one() { name=$1; shift; /usr/bin/time -f "$name %e s" $E complete --run $R --inpainter exemplar --device cpu --out $R/complete/$name "$@" > $R.$name.log 2>> /tmp/warmexp.times; }
( one init --method init --steps 1000; one ref --method reference --steps 1000; one direct --method direct --steps 1000 ) &
( one init_warm --method init --warm; one ref_warm --method reference --warm; one direct_warm --method direct --warm ) &
wait; echo done >> /tmp/warmexp.times
