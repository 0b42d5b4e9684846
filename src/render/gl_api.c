/* springpend (internal): GL function table and program building. */
#include <stddef.h>

#include "springpend/common.h"
#include "gl_api.h"

int sp_gl_api_load(struct sp_gl_api *gl, struct sp_gl_context *c)
{
#define X(type, name)                                                    \
    gl->name = (type)sp_gl_context_proc(c, "gl" #name);                  \
    if (!gl->name) {                                                     \
        sp_log_error("the GL context lacks gl" #name);                   \
        return SP_E_GL;                                                  \
    }
    SP_GL_FUNCS(X)
#undef X
    return 0;
}

/* Compiles one stage; returns 0 after logging the driver's message. */
static GLuint compile(const struct sp_gl_api *gl, GLenum type, const char *src,
                      const char *name)
{
    GLuint sh = gl->CreateShader(type);
    GLint ok = 0;
    char msg[1024] = "";

    gl->ShaderSource(sh, 1, &src, NULL);
    gl->CompileShader(sh);
    gl->GetShaderiv(sh, GL_COMPILE_STATUS, &ok);
    if (!ok) {
        gl->GetShaderInfoLog(sh, sizeof(msg), NULL, msg);
        sp_log_error("compiling %s.%s: %s", name, type == GL_VERTEX_SHADER ? "vert" : "frag",
                     msg);
        gl->DeleteShader(sh);
        return 0;
    }
    return sh;
}

int sp_gl_program_make(const struct sp_gl_api *gl, const char *vs_src, const char *fs_src,
                       const char *name, GLuint *program)
{
    GLuint vs = compile(gl, GL_VERTEX_SHADER, vs_src, name);
    GLuint fs = compile(gl, GL_FRAGMENT_SHADER, fs_src, name);
    GLint ok = 0;
    char msg[1024] = "";
    int err = SP_E_GL;

    if (!vs || !fs)
        goto done;
    *program = gl->CreateProgram();
    gl->AttachShader(*program, vs);
    gl->AttachShader(*program, fs);
    gl->LinkProgram(*program);
    gl->GetProgramiv(*program, GL_LINK_STATUS, &ok);
    if (!ok) {
        gl->GetProgramInfoLog(*program, sizeof(msg), NULL, msg);
        sp_log_error("linking the %s shaders: %s", name, msg);
        goto done;
    }
    err = 0;
done:
    if (vs)
        gl->DeleteShader(vs);
    if (fs)
        gl->DeleteShader(fs);
    return err;
}
