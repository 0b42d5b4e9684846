/* springpend (internal): the GL functions the renderer's passes call, looked
 * up once through the context backend (sp_gl_context_proc), and a helper that
 * builds a program from two embedded shader sources. */
#ifndef SPRINGPEND_GL_API_H
#define SPRINGPEND_GL_API_H

#include <GL/glcorearb.h>

#include "gl_context.h"

/* The framebuffer's functions (gl_offscreen.h) and the passes' own: one
 * table, each function once. */
#define SP_GL_FUNCS(X)                                              \
    SP_GL_OFFSCREEN_FUNCS(X)                                        \
    X(PFNGLGETSTRINGPROC, GetString)                                \
    X(PFNGLGETERRORPROC, GetError)                                  \
    X(PFNGLCREATESHADERPROC, CreateShader)                          \
    X(PFNGLSHADERSOURCEPROC, ShaderSource)                          \
    X(PFNGLCOMPILESHADERPROC, CompileShader)                        \
    X(PFNGLGETSHADERIVPROC, GetShaderiv)                            \
    X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                  \
    X(PFNGLDELETESHADERPROC, DeleteShader)                          \
    X(PFNGLCREATEPROGRAMPROC, CreateProgram)                        \
    X(PFNGLATTACHSHADERPROC, AttachShader)                          \
    X(PFNGLLINKPROGRAMPROC, LinkProgram)                            \
    X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                          \
    X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                \
    X(PFNGLUSEPROGRAMPROC, UseProgram)                              \
    X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)              \
    X(PFNGLUNIFORM1IPROC, Uniform1i)                                \
    X(PFNGLUNIFORM2FPROC, Uniform2f)                                \
    X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                    \
    X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                    \
    X(PFNGLGENBUFFERSPROC, GenBuffers)                              \
    X(PFNGLBINDBUFFERPROC, BindBuffer)                              \
    X(PFNGLBUFFERDATAPROC, BufferData)                              \
    X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                        \
    X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)    \
    X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)            \
    X(PFNGLVERTEXATTRIBDIVISORPROC, VertexAttribDivisor)            \
    X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                        \
    X(PFNGLVIEWPORTPROC, Viewport)                                  \
    X(PFNGLCLEARCOLORPROC, ClearColor)                              \
    X(PFNGLCLEARPROC, Clear)                                        \
    X(PFNGLENABLEPROC, Enable)                                      \
    X(PFNGLBLENDEQUATIONPROC, BlendEquation)                        \
    X(PFNGLBLENDFUNCSEPARATEPROC, BlendFuncSeparate)                \
    X(PFNGLDRAWARRAYSINSTANCEDPROC, DrawArraysInstanced)           \
    X(PFNGLBLITFRAMEBUFFERPROC, BlitFramebuffer)                    \
    X(PFNGLSCISSORPROC, Scissor)                                    \
    X(PFNGLREADBUFFERPROC, ReadBuffer)                              \
    X(PFNGLDRAWBUFFERSPROC, DrawBuffers)                            \
    X(PFNGLDISABLEPROC, Disable)

struct sp_gl_api {
#define X(type, name) type name;
    SP_GL_FUNCS(X)
#undef X
};

/* Fills gl from context c. 0, or SP_E_GL naming the first missing function. */
int sp_gl_api_load(struct sp_gl_api *gl, struct sp_gl_context *c);

/* Compiles and links vs + fs into *program. `name` ("shape", "text") names the
 * pair in the driver's messages. 0 or SP_E_GL (logged). */
int sp_gl_program_make(const struct sp_gl_api *gl, const char *vs, const char *fs,
                       const char *name, GLuint *program);

#endif
