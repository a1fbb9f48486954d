/* near_rows: what the run-time near terms of a file would hold at other
 * radii (docs/accuracy.md, "Near terms sized by the material"): for each
 * RADIUS_MM, the entries per row and the bytes a reader builds (an index
 * and a float per channel per entry), with the file's own mesh, scale and
 * material and the point rule.
 *
 *   near_rows FILE.sss RADIUS_MM...
 */
#include <stdio.h>
#include <stdlib.h>

#include "sss/format.h"
#include "sss/nearterms.h"

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: near_rows FILE.sss RADIUS_MM...\n");
        return 2;
    }
    sss_bake_file f;
    sss_error err = {{0}};
    if (sss_file_read(argv[1], &f, &err) != SSS_OK) {
        fprintf(stderr, "near_rows: %s\n", err.msg);
        return 1;
    }
    int rc = 0;
    for (int a = 2; a < argc && rc == 0; a++) {
        char *end;
        const double R = strtod(argv[a], &end);
        if (*end || !(R > 0.0)) {
            fprintf(stderr, "near_rows: radius '%s' is not a number > 0\n", argv[a]);
            rc = 2;
            break;
        }
        const sss_near_spec spec = {.radius_mm = R, .eps = f.eps};
        sss_weights w;
        if (sss_near_build_spec(&f.mesh, &f.material, f.mm_per_unit, f.channels, &spec, NULL, &w, &err) != SSS_OK) {
            fprintf(stderr, "near_rows: %s\n", err.msg);
            rc = 1;
            break;
        }
        const double n = (double)w.start[f.mesh.nv];
        printf("%s\t%u\t%.4g\t%.1f\t%.1f\n", argv[1], f.mesh.nv, R, n / f.mesh.nv, n * (4.0 + 4.0 * f.channels) / 1e6);
        sss_weights_free(&w);
    }
    sss_file_free(&f);
    return rc;
}
