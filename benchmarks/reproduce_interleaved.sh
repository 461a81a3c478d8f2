#!/bin/bash
# Two checkouts' reproductions on one machine, result by result, interleaved (ABBA: the order alternates from one
# result to the next), so that a drift of the machine's speed falls on both alike.
#
#   bash benchmarks/reproduce_interleaved.sh BEFORE_CHECKOUT AFTER_CHECKOUT OUT "NAME NAME ..."
#
# Each checkout needs its own environment in CHECKOUT/.venv (pip install -e CHECKOUT) and gets a numba cache of its
# own, empty at the start (both pay their compiles alike, in their first result). Writes OUT/before and OUT/after
# (each a `neurowalk reproduce` folder of those results) and OUT/times.tsv (name, side, exit status, wall s), then
# `python benchmarks/reproduction_times.py OUT/before OUT/after` compares them.
set -u
before=$1 after=$2 out=$3 names=$4
mkdir -p "$out"
i=0
for n in $names; do
  if [ $((i % 2)) -eq 0 ]; then order="before after"; else order="after before"; fi
  for side in $order; do
    if [ "$side" = before ]; then dir=$before; else dir=$after; fi
    s=$(date +%s.%N)
    (cd "$dir" && NUMBA_CACHE_DIR="$out/numba-$side" .venv/bin/neurowalk reproduce --only "$n" --out "$out/$side" \
      > "$out/$side-$n.log" 2>&1)
    rc=$?
    e=$(date +%s.%N)
    echo -e "$n\t$side\t$rc\t$(echo "$e - $s" | bc)" >> "$out/times.tsv"
  done
  i=$((i + 1))
done
