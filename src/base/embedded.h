/* springpend: files embedded at build time by shaders/embed.py.
 * Shared with: every folder. */
#ifndef SPRINGPEND_EMBEDDED_H
#define SPRINGPEND_EMBEDDED_H

extern const char sp_embed_shape_vert[];
extern const unsigned long sp_embed_shape_vert_size;
extern const char sp_embed_shape_frag[];
extern const unsigned long sp_embed_shape_frag_size;

extern const char sp_embed_text_vert[];
extern const char sp_embed_text_frag[];
extern const char sp_embed_yuv_vert[];
extern const char sp_embed_yuv_frag[];
extern const char sp_embed_DejaVuSans_ttf[];
extern const unsigned long sp_embed_DejaVuSans_ttf_size;

#endif
