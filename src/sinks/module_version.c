/* springpend: the version each module carries (module.h). The core
 * refuses a module whose version is not its own: a module of another
 * springpend would call into structures laid out differently. */
#include "module_abi.h"
#include "springpend/common.h"

__attribute__((visibility("default"))) const char sp_module_version[] = SP_VERSION;
/* the shared headers' id (shaders/abi.py): the same version number does not
 * mean the same structures and signatures between two builds */
__attribute__((visibility("default"))) const char sp_module_abi[] = SP_MODULE_ABI;
