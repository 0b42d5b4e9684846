/* springpend: files embedded at build time by shaders/embed.py. */
#ifndef SPRINGPEND_EMBEDDED_H
#define SPRINGPEND_EMBEDDED_H

extern const char sp_embed_shape_vert[];
extern const unsigned long sp_embed_shape_vert_size;
extern const char sp_embed_shape_frag[];
extern const unsigned long sp_embed_shape_frag_size;

#endif
