# accuracy_report_4000.sh: plots and docs/accuracy_4000.md from
# docs/data/accuracy_4000/results.jsonl (the 4000 mm/unit series). Sourced by accuracy_study.sh (which sets
# DATA, DOC, OUT, FULL, VIEWS); not run on its own. gnuplot for the plots,
# jq and awk for the tables.
. "$(dirname "${BASH_SOURCE[0]}")/accuracy_lib.sh"

# ---- data files for gnuplot
for m in bunny teapot d23 d100 d437 sphere; do
  for ip in triangle nearest4; do
    q --arg m "$m" --arg ip "$ip" 'map(select(.mesh==$m and .study=="dirs" and .interp==$ip)) | sort_by(.directions) | .[] |
      [.directions, .image.rms_max, .image.rms_mean, .vertex_rel_rms, .bytes_per_vertex, .bake_s.total] | @tsv' > "$P/fig5_${m}_${ip}.dat"
  done
done
# the directions sweep with the near terms (own term + 1-ring) at run time
for m in d23 sphere; do
  for ip in triangle map; do
    q --arg m "$m" --arg ip "$ip" 'map(select(.mesh==$m and .study=="dirs_ring1" and .interp==$ip)) | sort_by(.directions) | .[] |
      [.directions, .image.rms_max, .image.rms_mean, .vertex_rel_rms, .bytes_per_vertex, .bake_s.total] | @tsv' > "$P/fig5_${m}_ring1_${ip}.dat"
  done
done
for o in 3 6; do
  q --argjson o "$o" 'map(select(.mesh=="d23" and (.study=="refs") and .sh_order==$o)) | sort_by(.refs) | .[] |
    [.refs, .image.rms_max, .image.rms_mean, .vertex_rel_rms, .bytes_per_vertex] | @tsv' > "$P/fig9_o$o.dat"
done
# Pareto fronts over every d23 configuration (triangle interpolation):
# points, then the front (sorted by cost, keeping each point that lowers the error)
q 'map(select(.mesh=="d23" and .interp=="triangle")) | .[] | [.bytes_per_vertex, .bake_s.total, .cpu_scatter_ms, .image.rms_max, .id, .image.rms_mean] | @tsv' > "$P/pareto_d23.dat"
front 1 4 > "$P/front_bytes.dat"; front 2 4 > "$P/front_bake.dat"; front 3 4 > "$P/front_frame.dat"
front 1 6 > "$P/front_bytes_mean.dat"; front 2 6 > "$P/front_bake_mean.dat"; front 3 6 > "$P/front_frame_mean.dat"

plot fig5_error_vs_directions "
set logscale xy
set title 'Image RMS (max over $VIEWS views, as Hao-Varshney 2004 Fig. 5) vs number of light directions'
set xlabel 'light directions'
set ylabel 'image RMS error'
set xtics (25,50,100,200,400,800)
set xrange [20:1000]
set key bottom left
plot '$P/fig5_bunny_triangle.dat' u 1:2 w lp lw 2 t 'bunny, triangle', \
     '$P/fig5_teapot_triangle.dat' u 1:2 w lp lw 2 t 'teapot, triangle', \
     '$P/fig5_d23_triangle.dat' u 1:2 w lp lw 2 t 'dragon 23K, triangle', \
     '$P/fig5_d23_nearest4.dat' u 1:2 w lp dt 2 lw 2 t 'dragon 23K, 4 nearest (paper)', \
     '$P/fig5_teapot_nearest4.dat' u 1:2 w lp dt 2 lw 2 t 'teapot, 4 nearest (paper)', \
     '$P/fig5_d100_triangle.dat' u 1:2 w lp lw 2 t 'dragon 100K (lloyd8), triangle', \
     '$P/fig5_sphere_triangle.dat' u 1:2 w lp lw 2 lc rgb 'black' t 'sphere (no self-shadowing), triangle', \
     '$P/fig5_sphere_nearest4.dat' u 1:2 w lp dt 2 lw 2 lc rgb 'gray40' t 'sphere, 4 nearest (paper)', \
     3e-3 w l lc rgb 'red' dt 3 t 'paper: 3e-3 at 200 directions'"
plot fig5_mean_vs_directions "
set logscale xy
set title 'Image RMS (mean over $VIEWS views) and per-vertex relative RMS vs light directions'
set xlabel 'light directions'
set ylabel 'error'
set xtics (25,50,100,200,400,800)
plot '$P/fig5_bunny_triangle.dat' u 1:3 w lp lw 2 t 'bunny, image mean', \
     '$P/fig5_teapot_triangle.dat' u 1:3 w lp lw 2 t 'teapot, image mean', \
     '$P/fig5_d23_triangle.dat' u 1:3 w lp lw 2 t 'dragon 23K, image mean', \
     '$P/fig5_d23_triangle.dat' u 1:4 w lp dt 2 lw 2 t 'dragon 23K, per-vertex rel. RMS', \
     '$P/fig5_d23_nearest4.dat' u 1:3 w lp dt 3 lw 2 t 'dragon 23K, image mean, 4 nearest', \
     '$P/fig5_sphere_triangle.dat' u 1:3 w lp lw 2 lc rgb 'black' t 'sphere, image mean', \
     '$P/fig5_sphere_triangle.dat' u 1:4 w lp dt 2 lw 2 lc rgb 'black' t 'sphere, per-vertex rel. RMS'"
plot fig5_near_terms "
set logscale xy
set title 'Image RMS (max over $VIEWS views) vs light directions: all baked vs own term + 1-ring at run time'
set xlabel 'light directions'
set ylabel 'image RMS error'
set xtics (25,50,100,200,400,800)
set xrange [20:1000]
set key bottom left
plot '$P/fig5_d23_triangle.dat' u 1:2 w lp lw 2 lc rgb 'blue' t 'dragon 23K, all baked (paper)', \
     '$P/fig5_d23_ring1_triangle.dat' u 1:2 w lp lw 2 lc rgb 'blue' dt 2 t 'dragon 23K, near terms (viewer: rays)', \
     '$P/fig5_d23_ring1_map.dat' u 1:2 w lp lw 2 lc rgb 'dark-cyan' dt 4 t 'dragon 23K, near terms, viewer shadow map 2048', \
     '$P/fig5_sphere_triangle.dat' u 1:2 w lp lw 2 lc rgb 'black' t 'sphere, all baked', \
     '$P/fig5_sphere_ring1_triangle.dat' u 1:2 w lp lw 2 lc rgb 'black' dt 2 t 'sphere, near terms', \
     3e-3 w l lc rgb 'red' dt 3 t 'paper: 3e-3 at 200 directions', \
     1e-3 w l lc rgb 'dark-green' dt 4 t 'target: 1e-3'"
F200MAX=$(q 'map(select(.id=="d23_dirs200_float" and .interp=="triangle")) | .[0].image.rms_max // 0')
F200MEAN=$(q 'map(select(.id=="d23_dirs200_float" and .interp=="triangle")) | .[0].image.rms_mean // 0')
plot fig9_error_vs_references "
set logscale xy
set title 'Image RMS vs number of reference points (Hao-Varshney 2004 Fig. 9), dragon 23K, 200 directions'
set xlabel 'reference points'
set ylabel 'image RMS error'
set xrange [80:6000]
set key outside bottom center horizontal maxrows 3
plot '$P/fig9_o3.dat' u 1:2 w lp lw 2 t '9 coefficients (order 3), max', \
     '$P/fig9_o6.dat' u 1:2 w lp lw 2 t '36 coefficients (order 6), max', \
     '$P/fig9_o3.dat' u 1:3 w lp dt 2 lw 2 t '9 coefficients, mean', \
     '$P/fig9_o6.dat' u 1:3 w lp dt 2 lw 2 t '36 coefficients, mean', \
     $F200MAX w l lc rgb 'black' dt 3 t 'uncompressed float, max', \
     $F200MEAN w l lc rgb 'gray40' dt 4 t 'uncompressed float, mean'"
pareto_plot() { # name, title, x label, x column of pareto_d23.dat, front_<stem>.dat
  plot "$1" "
set logscale xy
set title '$2'
set xlabel '$3'
set ylabel 'image RMS'
plot '$P/pareto_d23.dat' u $4:4 w p pt 7 ps 0.8 t 'max over views', '$P/front_$5.dat' u 1:2 w steps lw 2 t 'front (max)', \\
     '$P/pareto_d23.dat' u $4:6 w p pt 6 ps 0.8 t 'mean over views', '$P/front_$5_mean.dat' u 1:2 w steps lw 2 dt 2 t 'front (mean)'"
}
pareto_plot pareto_error_bytes 'Error vs storage, dragon 23K: every configuration and the Pareto front' \
  'scattering bytes per vertex (everything counted)' 1 bytes
pareto_plot pareto_error_bake_time 'Error vs bake time, dragon 23K (2 shared cores)' 'bake seconds (total)' 2 bake
pareto_plot pareto_error_frame_time 'Error vs per-frame evaluation time (CPU decode, median of 10), dragon 23K' \
  'CPU scatter ms per frame' 3 frame

# ---- tables
table_dirs() {
  echo "| mesh | directions | interpolation | image RMS max | image RMS mean | per-vertex rel. RMS | bytes/vertex | bake s |"
  echo "|---|---|---|---|---|---|---|---|"
  q 'map(select(.study=="dirs")) | sort_by(.mesh, .directions, .interp) | .[] |
     [.mesh, .vertices, .directions, .interp, .quant, .image.rms_max, .image.rms_mean, .vertex_rel_rms, .bytes_per_vertex, .bake_s.total] | @tsv' |
  awk -F'\t' '{printf("| %s (%s v) | %d | %s | %.2e | %.2e | %.3f | %.0f (%s) | %.1f |\n", $1, $2, $3, $4, $6, $7, $8, $9, $5, $10)}'
}
table_one() {
  echo "| model | vertices | triangles | refs | B/vertex paper preset | ratio vs 8-bit | B/vertex compact | fps CPU path (paper preset) | fps GPU path (llvmpipe) | paper: refs | paper: B/vertex | paper: ratio | paper: fps |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
  for m in bunny teapot d23 d100 d437; do
    q --arg m "$m" '(map(select(.mesh==$m and .id==($m+"_paper"))) | .[0]) as $p | (map(select(.mesh==$m and .id==($m+"_compact"))) | .[0]) as $c |
       if $p then [$m, $p.vertices, $p.triangles, $p.refs, $p.bytes_per_vertex, $p.ratio_vs_8bit, ($c.bytes_per_vertex // 0), $p.cpu_fps, $p.gpu_fps] | @tsv else empty end' |
    awk -F'\t' '{printf("| %s | %s | %s | %s | %.1f | %.1f | %.1f | %.1f | %.1f | | | | |\n", $1, $2, $3, $4, $5, $6, $7, $8, $9)}'
  done
  echo "| *paper:* Horse | 14,521 | 29,054 | | | | | | | 1,034 | 27 | 7.4 | 79.1 |"
  echo "| *paper:* Teapot | 150,510 | 292,168 | | | | | | | 5,176 | 20 | 10.0 | 8.6 |"
  echo "| *paper:* Dragon | 437,645 | 871,414 | | | | | | | 10,285 | 18 | 11.1 | 2.7 |"
}

# least-squares exponent b of err ∝ N^b over the directions sweep (column c of fig5 data)
slope() { awk -v c="$2" '$c > 0 { x=log($1); y=log($c); n++; sx+=x; sy+=y; sxx+=x*x; sxy+=x*y }
  END { if (n >= 3) printf("%.2f", (n*sxy - sx*sy) / (n*sxx - sx*sx)); else printf("—") }' "$P/fig5_$1.dat"; }
table_slopes() {
  echo "| mesh | interpolation | image RMS max ∝ N^b | image RMS mean ∝ N^b | per-vertex rel. RMS ∝ N^b |"
  echo "|---|---|---|---|---|"
  for m in bunny teapot d23 d100 sphere; do for ip in triangle nearest4; do
    [ -s "$P/fig5_${m}_${ip}.dat" ] || continue
    echo "| $m | $ip | $(slope ${m}_$ip 2) | $(slope ${m}_$ip 3) | $(slope ${m}_$ip 4) |"
  done; done
}
# near terms at 200 directions: all baked, own term, +1 ring, +2 rings
table_near() {
  echo "| mesh | near terms at run time | bytes/vertex | image RMS max | image RMS mean | per-vertex rel. RMS | bake s | CPU path ms | GPU path ms |"
  echo "|---|---|---|---|---|---|---|---|---|"
  for m in sphere bunny teapot d23 d100; do
    for id in "${m}_dirs200_float" "${m}_dirs200_ring0" "${m}_dirs200_ring1" "${m}_dirs200_ring2" "${m}_dirs200_lloyd8" "${m}_dirs200_lloyd8_ring1" "${m}_dirs200_lloyd8_ring2"; do
      q --arg id "$id" 'map(select(.id==$id and (.interp=="triangle" or .interp=="map"))) | .[] |
        [.id, .mesh, .quant, .bytes_per_vertex, .image.rms_max, .image.rms_mean, .vertex_rel_rms, .bake_s.total, .cpu_scatter_ms, .gpu_scatter_ms, .interp, (.image.near_visibility // "")] | @tsv' |
      awk -F'\t' '{ k = "none (paper)"; if ($1 ~ /ring0$/) k = "own term"; else if ($1 ~ /ring1$/) k = "own + 1-ring"; else if ($1 ~ /ring2$/) k = "own + 2 rings";
        if ($12 != "") k = k ", " $12;
        printf("| %s | %s | %.0f (%s) | %.2e | %.2e | %.4f | %.1f | %.2f | %.2f |\n", $2, k, $4, $3, $5, $6, $7, $8, $9, $10) }'
    done
  done
}
# error_sources: per-vertex rel. RMS by what the interpolation fails to follow
table_sources() {
  echo "| float bake, 200 directions | all baked | without cast shadows (V ≡ 1) | share of squared error where the vertex's own visibility flips (pairs) | linear weights | terminator divided out | own term at run time | own + 1-ring | own + 2 rings |"
  echo "|---|---|---|---|---|---|---|---|---|"
  [ -s "$DATA/error_sources.jsonl" ] || return 0
  jq -r '[(.file | sub(".*/"; "") | sub(".sss$"; "")), .vertices, .shadows.triangle, .no_shadows.triangle,
          .split.shadow_edge.error_share, .split.shadow_edge.area_share, .shadows.linear, .shadows.terminator,
          .shadows.own, .shadows.own_ring1, .shadows.own_ring2] | @tsv' "$DATA/error_sources.jsonl" |
  awk -F'\t' '{printf("| %s (%s v) | %.4f | %.4f | %.1f %% (%.1f %%) | %.4f | %.4f | %.4f | %.5f | %.5f |\n", $1, $2, $3, $4, 100*$5, 100*$6, $7, $8, $9, $10, $11)}'
}
GL=$(q '.[0].gl_renderer // "unknown"')
N_CFG=$(q 'length')

. "$(dirname "${BASH_SOURCE[0]}")/accuracy_doc_4000.sh" > "$DOC"
