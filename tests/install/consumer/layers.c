/* The installed libsss_bake and libsss_render from outside the source tree
 * (docs/install.md): imports a mesh with libsss_bake's reader and prints
 * its size and the renderer's default exposure, so that linking pulls in
 * both libraries and what they depend on. Usage: layers MESH */
#include <stdio.h>
#include "sss/import.h"
#include "sss/render.h"

int main(int argc, char **argv)
{
    if (argc != 2) {
        fprintf(stderr, "usage: layers MESH\n");
        return 2;
    }
    sss_mesh m;
    sss_import_report rep;
    sss_error err = {{0}};
    if (sss_import_mesh(argv[1], &m, &rep, &err) != SSS_OK) {
        fprintf(stderr, "layers: %s\n", err.msg);
        return 1;
    }
    sss_view_params p;
    sss_view_params_default(&p);
    printf("vertices %u triangles %u exposure %g\n", m.nv, m.nf, p.exposure);
    sss_mesh_free(&m);
    return 0;
}
