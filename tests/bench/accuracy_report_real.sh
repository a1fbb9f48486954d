# accuracy_report_real.sh: plots and docs/accuracy.md from
# docs/data/accuracy/results.jsonl (the real-size series). Sourced by
# accuracy_study.sh (which sets DATA, DOC, OUT, FULL, VIEWS); not run on
# its own. gnuplot for the plots, jq and awk for the tables.
. "$(dirname "${BASH_SOURCE[0]}")/accuracy_lib.sh"

# ---- data files for gnuplot
# error against the number of directions at the defaults (200 is the
# defaults row itself)
for m in d23 bunny sphere; do
  q --arg m "$m" 'map(select(.mesh==$m and .interp=="triangle" and (.study=="dirs" or .study=="defaults"))) | sort_by(.directions) | .[] |
    [.directions, .image.rms_max, .image.rms_mean, (.backlit.rms_max // 0), (.backlit.rms_mean // 0), .bytes_per_vertex] | @tsv' > "$P/dirs_$m.dat"
done
# the near terms' fraction (0.95 is the defaults row)
for m in d23 bunny; do
  q --arg m "$m" 'map(select(.mesh==$m and .interp=="triangle" and (.study=="fraction" or .study=="defaults"))) |
    map(. + {f: ((.bake_args | capture("--near-fraction (?<f>[0-9.]+)").f // "0.95") | tonumber)}) | sort_by(.f) | .[] |
    [.f, .image.rms_max, (.backlit.rms_max // 0), .gpu_scatter_ms, .cpu_scatter_ms, .near_entries_per_vertex] | @tsv' > "$P/fraction_$m.dat"
done
# every configuration of the 23K dragon, its worse of the random and
# back-lit maxima against each cost, and the front (each point that lowers
# the error as the cost grows)
q "$ERR"' map(select(.mesh=="d23" and .interp=="triangle")) | .[] | [.bytes_per_vertex, .bake_s.total, .gpu_scatter_ms, err("worst"), .id] | @tsv' > "$P/pareto_d23.dat"
front 1 4 > "$P/front_bytes.dat"; front 3 4 > "$P/front_frame.dat"

plot real_error_vs_directions "
set logscale xy
set title 'Image RMS (worst of $VIEWS views) vs light directions, every other setting at the defaults, real sizes'
set xlabel 'light directions'
set ylabel 'image RMS error'
set xtics (50,100,200,400)
set xrange [40:500]
set yrange [1e-4:1e-2]
set format y '%.0e'
set key top right
plot '$P/dirs_d23.dat' u 1:2 w lp lw 2 lc rgb 'blue' t 'dragon 23K (20 cm), random views', \
     '$P/dirs_d23.dat' u 1:4 w lp lw 2 dt 2 lc rgb 'blue' t 'dragon 23K, back-lit', \
     '$P/dirs_bunny.dat' u 1:2 w lp lw 2 lc rgb 'dark-orange' t 'bunny (10 cm), random', \
     '$P/dirs_bunny.dat' u 1:4 w lp lw 2 dt 2 lc rgb 'dark-orange' t 'bunny, back-lit', \
     '$P/dirs_sphere.dat' u 1:2 w lp lw 2 lc rgb 'black' t 'sphere (10 cm), random', \
     '$P/dirs_sphere.dat' u 1:4 w lp lw 2 dt 2 lc rgb 'black' t 'sphere, back-lit', \
     1e-3 w l lc rgb 'dark-green' dt 4 t 'target: 1e-3'"
plot real_near_fraction "
set logscale y
set format y '%.0e'
set title 'The near terms sized by the fraction of R_d,total their radius holds: error and frame time'
set xlabel 'fraction f of R_d,total within the near radius'
set ylabel 'image RMS (worst of $VIEWS views)'
set y2label 'GPU-path ms per frame (llvmpipe)'
set y2tics
set ytics nomirror
set key top center
plot '$P/fraction_d23.dat' u 1:2 w lp lw 2 lc rgb 'blue' t 'dragon 23K, random', \
     '$P/fraction_d23.dat' u 1:3 w lp lw 2 dt 2 lc rgb 'blue' t 'dragon 23K, back-lit', \
     '$P/fraction_bunny.dat' u 1:2 w lp lw 2 lc rgb 'dark-orange' t 'bunny, random', \
     '$P/fraction_bunny.dat' u 1:3 w lp lw 2 dt 2 lc rgb 'dark-orange' t 'bunny, back-lit', \
     '$P/fraction_d23.dat' u 1:4 axes x1y2 w lp lw 1 pt 4 lc rgb 'gray40' t 'dragon 23K, GPU ms (right axis)'"
plot real_pareto "
set logscale xy
set format y '%.0e'
set multiplot layout 1,2 title 'Dragon 23K (20 cm): every configuration, worse of random and back-lit maxima'
set xlabel 'bytes per vertex (every byte but the mesh)'
set ylabel 'image RMS'
plot '$P/pareto_d23.dat' u 1:4 w p pt 7 ps 0.8 notitle, '$P/front_bytes.dat' u 1:2 w steps lw 2 t 'front'
set xlabel 'GPU-path ms per frame (llvmpipe)'
plot '$P/pareto_d23.dat' u 3:4 w p pt 7 ps 0.8 notitle, '$P/front_frame.dat' u 1:2 w steps lw 2 t 'front'
unset multiplot"

# ---- tables
# every configuration of a mesh, in the order measured: what was varied
# against the defaults, and what it costs
table_mesh() { # mesh
  echo "| configuration (flags added to the defaults) | B/vertex | near radius mm (entries/vertex) | image RMS worst | mean | back-lit worst | back-lit mean | per-vertex rel. RMS | bake s | GPU ms | CPU ms |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|"
  q --arg m "$1" 'map(select(.mesh==$m and .interp=="triangle")) | .[] |
    [(if .bake_args == "" then "(defaults)" else .bake_args end), .bytes_per_vertex, (.near_radius_mm // 0), (.near_entries_per_vertex // 0),
     .image.rms_max, .image.rms_mean, (.backlit.rms_max // 0), (.backlit.rms_mean // 0), .vertex_rel_rms, .bake_s.total, .gpu_scatter_ms, .cpu_scatter_ms] | @tsv' |
  awk -F'\t' '{ nr = ($3 > 0 ? sprintf("%.2f (%.1f)", $3, $4) : "—");
    printf("| `%s` | %.1f | %s | %.2e | %.2e | %.2e | %.2e | %.4f | %.1f | %.1f | %.1f |\n", $1, $2, nr, $5, $6, $7, $8, $9, $10, $11, $12) }' |
  sed 's/`(defaults)`/**defaults**/'
}
# the 4 nearest directions (the paper's interpolation) against the
# spherical triangle, on the defaults
table_interp() {
  echo "| file | interpolation | image RMS worst | mean | back-lit worst | back-lit mean | per-vertex rel. RMS |"
  echo "|---|---|---|---|---|---|---|"
  q 'map(select(.study=="defaults" and .mesh=="d23")) | .[] | [.mesh, .interp, .image.rms_max, .image.rms_mean, (.backlit.rms_max // 0), (.backlit.rms_mean // 0), .vertex_rel_rms] | @tsv' |
  awk -F'\t' '{printf("| %s defaults | %s | %.2e | %.2e | %.2e | %.2e | %.4f |\n", $1, $2, $3, $4, $5, $6, $7)}'
}
GL=$(q '.[0].gl_renderer // "unknown"')
N_CFG=$(q 'length')

. "$(dirname "${BASH_SOURCE[0]}")/accuracy_doc.sh" > "$DOC"
