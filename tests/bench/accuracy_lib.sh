# accuracy_lib.sh: helpers for the accuracy pages (docs/accuracy.md,
# docs/accuracy_4000.md), sourced by accuracy_report_real.sh and
# accuracy_report_4000.sh with DATA, OUT and VIEWS set: queries on
# $DATA/results.jsonl, number formats, gnuplot plots and the tables both
# pages share.
R="$DATA/results.jsonl"
P="$OUT/plot"   # gnuplot inputs: scratch, not part of the docs
mkdir -p "$P"
q() { jq -r -s "$@" "$R"; }
# median of the numbers on stdin
median() { sort -g | awk '{a[NR]=$1} END { if (NR) print (NR % 2 ? a[(NR+1)/2] : 0.5*(a[NR/2]+a[NR/2+1])); }'; }
fmt1() { awk -v x="$1" 'BEGIN { if (x == "" || x == "null") print "—"; else printf("%.1f", x) }'; }
fmt() { awk -v x="$1" 'BEGIN { if (x == "" || x == "null") print "—"; else printf("%.2e", x) }' | sed 's/e-0/e-/; s/e+0/e+/'; }

plot() { # name, gnuplot body (after the terminal and output lines)
  for t in png svg; do
    if [ $t = png ]; then term="pngcairo size 900,600 font 'Sans,11'"; else term="svg size 900,600 font 'Sans,11'"; fi
    gnuplot 2>"$P/$1.log" <<GP || echo "accuracy_report: plot $1 ($t) failed (no data yet?): $(tail -1 "$P/$1.log")" >&2
set terminal $term
set output "$DATA/$1.$t"
set grid
set key top right
$2
GP
  done
}

# The Pareto front of $P/pareto_d23.dat (tab-separated, the id in column
# 5): front COST-COLUMN ERROR-COLUMN prints cost, error and id of each
# point that lowers the error as the cost grows.
front() { sort -g -k"$1","$1" "$P/pareto_d23.dat" | awk -v c="$1" -v e="$2" -F'\t' 'BEGIN{b=1e30} $e < b { b=$e; print $c "\t" $e "\t" $5 }'; }
row() { awk -F'\t' -v OFS=' | ' "$@"; }
get() { q --arg id "$1" --arg ip "${3:-triangle}" "map(select(.id==\$id and .interp==\$ip)) | .[0] | $2 // empty"; }

table_generic() { # jq select expression
  echo "| configuration | bytes/vertex | image RMS max | image RMS mean | per-vertex rel. RMS | bake s (compress s) | peak RSS MiB | CPU decode ms | GPU path ms |"
  echo "|---|---|---|---|---|---|---|---|---|"
  q "map(select($1)) | .[] | [.id, .bytes_per_vertex, .image.rms_max, .image.rms_mean, .vertex_rel_rms, .bake_s.total, (.bake_s.compress // 0), .peak_rss_mib, .cpu_scatter_ms, .gpu_scatter_ms] | @tsv" |
  awk -F'\t' '{printf("| %s | %.2f | %.2e | %.2e | %.3f | %.1f (%.1f) | %.0f | %.2f | %.2f |\n", $1, $2, $3, $4, $5, $6, $7, $8, $9, $10)}'
}
# The error of a row by criterion: rms_max (the paper's, worst of the random
# views), rms_mean, or worst (the worse of the random and the back-lit
# views' maxima; rows without back-lit views: the random views').
ERR='def err($c): if $c == "worst" then ([.image.rms_max, (.backlit.rms_max // 0)] | max) else .image[$c] end;'
# cheapest configuration of a mesh (triangle interpolation) whose image RMS
# is at most T, by storage (bytes), bake time (bake) or GPU-path frame
# time (frame)
choose() { # mesh target key [criterion]
  q --arg m "$1" --argjson t "$2" --arg k "$3" --arg c "${4:-rms_max}" "$ERR"' map(select(.mesh==$m and .interp=="triangle" and err($c) <= $t)) |
     sort_by(if $k=="bytes" then .bytes_per_vertex elif $k=="frame" then .gpu_scatter_ms else .bake_s.total end) | .[0] //empty |
     [.id, .bytes_per_vertex, .bake_s.total, .cpu_scatter_ms, err($c), .bake_args, .gpu_scatter_ms] | @tsv' |
  awk -F'\t' -v k="$3" '{ c = ($6 == "" ? "defaults" : "`" $6 "`");
    if (k == "frame") printf("%s: %.1f B/vertex, GPU path %.1f ms, CPU %.1f ms, RMS %.2e", c, $2, $7, $4, $5);
    else printf("%s: %.1f B/vertex, bake %.1f s, CPU decode %.2f ms, RMS %.2e", c, $2, $3, $4, $5) }'
}
best() { # mesh [criterion]: the lowest error measured
  q --arg m "$1" --arg c "${2:-rms_max}" "$ERR"' map(select(.mesh==$m and .interp=="triangle")) | sort_by(err($c)) | .[0] |
     [.id, err($c), .bytes_per_vertex] | @tsv' | awk -F'\t' '{printf("none; lowest %.2e (%s, %.0f B/vertex)", $2, $1, $3)}'
}
# MESHES: the meshes with rows; KEYS: the columns (bytes, frame, bake)
table_choose() { # criterion
  local m t k line
  printf '| mesh | target |'; for k in $KEYS; do printf ' cheapest in %s |' "$(case $k in bytes) echo bytes;; frame) echo "frame time";; *) echo "bake time";; esac)"; done; echo
  printf '|---|---|'; for k in $KEYS; do printf -- '---|'; done; echo
  for m in $MESHES; do for t in 1e-2 3e-3 1e-3 3e-4; do
    line="| $m | $t |"
    for k in $KEYS; do
      b=$(choose $m $t $k "$1")
      if [ -z "$b" ] && [ "$k" = "${KEYS%% *}" ]; then b=$(best $m "$1"); fi
      line="$line ${b:-—} |"
    done
    echo "$line"
  done; done
}
