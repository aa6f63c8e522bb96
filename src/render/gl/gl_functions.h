#pragma once
// The OpenGL entry points of the two GL backends (osmesa: GL 4.5 core; gles: OpenGL ES 3.0), loaded
// through the platform's GetProcAddress so nothing links against libGL / libGLESv2 directly. Only the
// OpenGL ES 3.0 subset is used: every one of these is also core GL 4.5 with the same enums, so one plan
// executor (gl_plan.cpp) serves both. Internal to src/render; include it only where no desktop GL header is.
#define GL_GLES_PROTOTYPES 0
#include <GLES3/gl3.h>

namespace aovar::render::gl {

#define AOVAR_GL_FUNCTIONS(X)                                          \
  X(PFNGLGETSTRINGPROC, GetString)                                     \
  X(PFNGLGETSTRINGIPROC, GetStringi)                                   \
  X(PFNGLGETINTEGERVPROC, GetIntegerv)                                 \
  X(PFNGLGETSHADERPRECISIONFORMATPROC, GetShaderPrecisionFormat)       \
  X(PFNGLGETERRORPROC, GetError)                                       \
  X(PFNGLFINISHPROC, Finish)                                           \
  X(PFNGLENABLEPROC, Enable)                                           \
  X(PFNGLDISABLEPROC, Disable)                                         \
  X(PFNGLDEPTHFUNCPROC, DepthFunc)                                     \
  X(PFNGLDEPTHMASKPROC, DepthMask)                                     \
  X(PFNGLVIEWPORTPROC, Viewport)                                       \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                                 \
  X(PFNGLREADBUFFERPROC, ReadBuffer)                                   \
  X(PFNGLREADPIXELSPROC, ReadPixels)                                   \
  X(PFNGLGENBUFFERSPROC, GenBuffers)                                   \
  X(PFNGLBINDBUFFERPROC, BindBuffer)                                   \
  X(PFNGLBUFFERDATAPROC, BufferData)                                   \
  X(PFNGLBUFFERSUBDATAPROC, BufferSubData)                             \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                             \
  X(PFNGLBINDBUFFERBASEPROC, BindBufferBase)                           \
  X(PFNGLGENVERTEXARRAYSPROC, GenVertexArrays)                         \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                   \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                         \
  X(PFNGLVERTEXATTRIBPOINTERPROC, VertexAttribPointer)                 \
  X(PFNGLENABLEVERTEXATTRIBARRAYPROC, EnableVertexAttribArray)         \
  X(PFNGLGENTEXTURESPROC, GenTextures)                                 \
  X(PFNGLBINDTEXTUREPROC, BindTexture)                                 \
  X(PFNGLACTIVETEXTUREPROC, ActiveTexture)                             \
  X(PFNGLTEXSTORAGE2DPROC, TexStorage2D)                               \
  X(PFNGLTEXPARAMETERIPROC, TexParameteri)                             \
  X(PFNGLDELETETEXTURESPROC, DeleteTextures)                           \
  X(PFNGLGENRENDERBUFFERSPROC, GenRenderbuffers)                       \
  X(PFNGLBINDRENDERBUFFERPROC, BindRenderbuffer)                       \
  X(PFNGLRENDERBUFFERSTORAGEPROC, RenderbufferStorage)                 \
  X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)                 \
  X(PFNGLGENFRAMEBUFFERSPROC, GenFramebuffers)                         \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                         \
  X(PFNGLFRAMEBUFFERTEXTURE2DPROC, FramebufferTexture2D)               \
  X(PFNGLFRAMEBUFFERRENDERBUFFERPROC, FramebufferRenderbuffer)         \
  X(PFNGLDRAWBUFFERSPROC, DrawBuffers)                                 \
  X(PFNGLCHECKFRAMEBUFFERSTATUSPROC, CheckFramebufferStatus)           \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                   \
  X(PFNGLCLEARBUFFERFVPROC, ClearBufferfv)                             \
  X(PFNGLCREATESHADERPROC, CreateShader)                               \
  X(PFNGLSHADERSOURCEPROC, ShaderSource)                               \
  X(PFNGLCOMPILESHADERPROC, CompileShader)                             \
  X(PFNGLGETSHADERIVPROC, GetShaderiv)                                 \
  X(PFNGLGETSHADERINFOLOGPROC, GetShaderInfoLog)                       \
  X(PFNGLDELETESHADERPROC, DeleteShader)                               \
  X(PFNGLCREATEPROGRAMPROC, CreateProgram)                             \
  X(PFNGLATTACHSHADERPROC, AttachShader)                               \
  X(PFNGLDETACHSHADERPROC, DetachShader)                               \
  X(PFNGLBINDATTRIBLOCATIONPROC, BindAttribLocation)                   \
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                                 \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                               \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                     \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                             \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                                   \
  X(PFNGLGETUNIFORMBLOCKINDEXPROC, GetUniformBlockIndex)               \
  X(PFNGLUNIFORMBLOCKBINDINGPROC, UniformBlockBinding)                 \
  X(PFNGLGETUNIFORMLOCATIONPROC, GetUniformLocation)                   \
  X(PFNGLUNIFORM1IPROC, Uniform1i)                                     \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                                   \
  X(PFNGLDRAWELEMENTSPROC, DrawElements)                               \
  X(PFNGLISTEXTUREPROC, IsTexture)                                     \
  X(PFNGLISRENDERBUFFERPROC, IsRenderbuffer)                           \
  X(PFNGLISFRAMEBUFFERPROC, IsFramebuffer)                             \
  X(PFNGLISBUFFERPROC, IsBuffer)                                       \
  X(PFNGLISPROGRAMPROC, IsProgram)                                     \
  X(PFNGLISSHADERPROC, IsShader)

struct Functions {
#define AOVAR_GL_MEMBER(type, name) type name = nullptr;
  AOVAR_GL_FUNCTIONS(AOVAR_GL_MEMBER)
#undef AOVAR_GL_MEMBER
};

}  // namespace aovar::render::gl
