/* springpend (internal): SHA-256 digests as text. The hashing is nettle's
 * (struct sha256_ctx, sha256_init, sha256_update); nettle is small and
 * loads nothing else, so every command can link it.
 * Shared with: every folder. */
#ifndef SPRINGPEND_DIGEST_H
#define SPRINGPEND_DIGEST_H

#include <nettle/sha2.h>

/* Finishes ctx (nettle then starts it again) and writes its digest as 64
 * lowercase hex digits and a NUL into hex. */
void sp_digest_hex(struct sha256_ctx *ctx, char hex[65]);

#endif
