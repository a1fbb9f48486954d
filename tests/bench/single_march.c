/* single_march: seed 002's ray march (Algorithm 1) and the per-segment
 * closed form against the flat layered closed form (sss/single.h), over a
 * picture of view directions, at the paper's sample counts (Table 2: 10,
 * 50, 100), with the CPU time per evaluation (docs/layers.md §6).
 *
 * The material is seed 002's Table 1 (dermis 0.3 mm, blood 0.5 mm below
 * it, organs beneath), Schlick's phase as the paper uses, no Fresnel (the
 * paper's model); the light 30° from the normal; the picture is 64 × 64
 * view directions, cos θ_o in (0, 1] by 64 and φ by 64; the march reaches
 * 3 mm deep (Eq. 15's Depth_max). Usage: single_march [REPEATS] */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "sss/clock.h"
#include "sss/single.h"

int main(int argc, char **argv)
{
    const int reps = argc > 1 ? atoi(argv[1]) : 20;
    const sss_layer_stack st = {3,
                                {{{2.0, 1.0, 1.0}, {2.6, 1.6, 1.6}, 0.25, 0.3},
                                 {{6.0, 3.0, 2.0}, {6.6, 3.6, 2.6}, 0.40, 0.8},
                                 {{1.0, 1.0, 2.0}, {1.5, 1.5, 2.5}, 0.80, 3.0}},
                                SSS_PHASE_SCHLICK};
    const double n[3] = {0, 0, 1}, ti = 30.0 * 3.14159265358979323846 / 180.0, wi[3] = {sin(ti), 0, cos(ti)};
    const double depth = 3.0;
    const uint32_t Ns[] = {10, 50, 100};
    printf("| N | Algorithm 1: RMS rel. error | max | RMS where cos θ_o ≥ 0.5 | per-segment: RMS rel. error | max | "
           "Algorithm 1 ns/eval | per-segment ns/eval |\n");
    printf("|---|---|---|---|---|---|---|---|\n");
    for (size_t q = 0; q < 3; q++) {
        double se[2] = {0, 0}, mx[2] = {0, 0}, t[2] = {0, 0}, se_hi = 0;
        long cnt = 0, cnt_hi = 0;
        for (int mode = 0; mode < 2; mode++) {
            double sink = 0;
            const double t0 = sss_now();
            for (int r = 0; r < reps; r++)
                for (int a = 0; a < 64; a++)
                    for (int b = 0; b < 64; b++) {
                        const double mu = (a + 0.5) / 64, phi = 2.0 * 3.14159265358979323846 * (b + 0.5) / 64;
                        const double wo[3] = {sqrt(1 - mu * mu) * cos(phi), sqrt(1 - mu * mu) * sin(phi), mu};
                        sss_ss_geom g;
                        sss_ss_geometry(n, wi, wo, 1.0, 0, &g);
                        sss_ss_flat f = {&st, g.mu_i, g.mu_o};
                        for (uint32_t c = 0; c < 3; c++) {
                            const double L = mode ? sss_ss_march_segments(&st, c, &g, depth / g.mu_o, Ns[q], sss_ss_locate_flat, &f)
                                                  : sss_ss_march(&st, c, &g, depth / g.mu_o, Ns[q], sss_ss_locate_flat, &f);
                            sink += L;
                            if (r == 0) {
                                const double ex = sss_layers_closed(&st, c, &g), e = fabs(L - ex) / ex;
                                se[mode] += e * e;
                                mx[mode] = fmax(mx[mode], e);
                                if (mode == 0) cnt++;
                                if (mode == 0 && mu >= 0.5) se_hi += e * e, cnt_hi++;
                            }
                        }
                    }
            t[mode] = (sss_now() - t0) / ((double)reps * 64 * 64 * 3) * 1e9;
            if (sink < 0) puts("");
        }
        printf("| %u | %.4f | %.4f | %.4f | %.2e | %.2e | %.0f | %.0f |\n", Ns[q], sqrt(se[0] / cnt), mx[0],
               sqrt(se_hi / cnt_hi), sqrt(se[1] / cnt), mx[1], t[0], t[1]);
    }
    return 0;
}
