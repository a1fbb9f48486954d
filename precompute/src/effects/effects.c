/* effects.c: the table of effect units (effects/effect.h), in pass-kind
 * order: the order the planner records them in and the scene bake runs
 * their passes in. */
#include "effects/effect.h"

const sss_effect_unit *const sss_effect_units[SSS_PASS_KINDS] = {
    [SSS_PASS_DIR_EXACT] = &sss_effect_dir_exact,
    [SSS_PASS_DIR_SET] = &sss_effect_dir_set,
    [SSS_PASS_POINT_SHELLS] = &sss_effect_point_shells,
    [SSS_PASS_ENV_SH] = &sss_effect_env_sh,
};
