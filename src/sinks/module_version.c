/* springpend: the version each module carries (av_module.h). The core
 * refuses a module whose version is not its own: a module of another
 * springpend would call into structures laid out differently. */
#include "springpend/common.h"

__attribute__((visibility("default"))) const char sp_module_version[] = SP_VERSION;
