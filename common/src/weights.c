/* weights.c: the compressed rows of sss/weights.h. */
#include "sss/weights.h"

#include <stdlib.h>
#include <string.h>

void sss_weights_free(sss_weights *w)
{
    if (!w) return;
    free(w->start);
    free(w->idx);
    free(w->w);
    memset(w, 0, sizeof *w);
}
