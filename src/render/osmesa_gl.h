#pragma once
// OpenGL 4.5 core entry points of the osmesa backend, loaded through OSMesaGetProcAddress: libOSMesa
// exports only some gl* symbols, so nothing here links against them directly. Internal to src/render.
#include <GL/glcorearb.h>  // before osmesa.h: its gl.h then adds nothing the core header lacks
#include <GL/osmesa.h>

namespace aovar::render::osmesa {

// Every GL function the backend calls. Direct state access (4.5) keeps object setup free of bind points.
#define AOVAR_GL_FUNCTIONS(X)                                          \
  X(PFNGLGETSTRINGPROC, GetString)                                     \
  X(PFNGLGETERRORPROC, GetError)                                       \
  X(PFNGLFINISHPROC, Finish)                                           \
  X(PFNGLENABLEPROC, Enable)                                           \
  X(PFNGLDISABLEPROC, Disable)                                         \
  X(PFNGLDEPTHFUNCPROC, DepthFunc)                                     \
  X(PFNGLDEPTHMASKPROC, DepthMask)                                     \
  X(PFNGLVIEWPORTPROC, Viewport)                                       \
  X(PFNGLPIXELSTOREIPROC, PixelStorei)                                 \
  X(PFNGLCREATEBUFFERSPROC, CreateBuffers)                             \
  X(PFNGLNAMEDBUFFERSTORAGEPROC, NamedBufferStorage)                   \
  X(PFNGLNAMEDBUFFERSUBDATAPROC, NamedBufferSubData)                   \
  X(PFNGLDELETEBUFFERSPROC, DeleteBuffers)                             \
  X(PFNGLBINDBUFFERBASEPROC, BindBufferBase)                           \
  X(PFNGLCREATEVERTEXARRAYSPROC, CreateVertexArrays)                   \
  X(PFNGLDELETEVERTEXARRAYSPROC, DeleteVertexArrays)                   \
  X(PFNGLBINDVERTEXARRAYPROC, BindVertexArray)                         \
  X(PFNGLVERTEXARRAYVERTEXBUFFERPROC, VertexArrayVertexBuffer)         \
  X(PFNGLVERTEXARRAYELEMENTBUFFERPROC, VertexArrayElementBuffer)       \
  X(PFNGLVERTEXARRAYATTRIBFORMATPROC, VertexArrayAttribFormat)         \
  X(PFNGLVERTEXARRAYATTRIBBINDINGPROC, VertexArrayAttribBinding)       \
  X(PFNGLENABLEVERTEXARRAYATTRIBPROC, EnableVertexArrayAttrib)         \
  X(PFNGLCREATETEXTURESPROC, CreateTextures)                           \
  X(PFNGLTEXTURESTORAGE2DPROC, TextureStorage2D)                       \
  X(PFNGLTEXTUREPARAMETERIPROC, TextureParameteri)                     \
  X(PFNGLGENTEXTURESPROC, GenTextures)                                 \
  X(PFNGLTEXTUREVIEWPROC, TextureView)                                 \
  X(PFNGLCLEARTEXIMAGEPROC, ClearTexImage)                             \
  X(PFNGLGETTEXTUREIMAGEPROC, GetTextureImage)                         \
  X(PFNGLDELETETEXTURESPROC, DeleteTextures)                           \
  X(PFNGLBINDTEXTURESPROC, BindTextures)                               \
  X(PFNGLCREATERENDERBUFFERSPROC, CreateRenderbuffers)                 \
  X(PFNGLNAMEDRENDERBUFFERSTORAGEPROC, NamedRenderbufferStorage)       \
  X(PFNGLDELETERENDERBUFFERSPROC, DeleteRenderbuffers)                 \
  X(PFNGLCREATEFRAMEBUFFERSPROC, CreateFramebuffers)                   \
  X(PFNGLNAMEDFRAMEBUFFERTEXTUREPROC, NamedFramebufferTexture)         \
  X(PFNGLNAMEDFRAMEBUFFERRENDERBUFFERPROC, NamedFramebufferRenderbuffer) \
  X(PFNGLNAMEDFRAMEBUFFERDRAWBUFFERSPROC, NamedFramebufferDrawBuffers) \
  X(PFNGLCHECKNAMEDFRAMEBUFFERSTATUSPROC, CheckNamedFramebufferStatus) \
  X(PFNGLDELETEFRAMEBUFFERSPROC, DeleteFramebuffers)                   \
  X(PFNGLBINDFRAMEBUFFERPROC, BindFramebuffer)                         \
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
  X(PFNGLLINKPROGRAMPROC, LinkProgram)                                 \
  X(PFNGLGETPROGRAMIVPROC, GetProgramiv)                               \
  X(PFNGLGETPROGRAMINFOLOGPROC, GetProgramInfoLog)                     \
  X(PFNGLDELETEPROGRAMPROC, DeleteProgram)                             \
  X(PFNGLUSEPROGRAMPROC, UseProgram)                                   \
  X(PFNGLDRAWARRAYSPROC, DrawArrays)                                   \
  X(PFNGLDRAWELEMENTSPROC, DrawElements)                               \
  X(PFNGLISTEXTUREPROC, IsTexture)                                     \
  X(PFNGLISRENDERBUFFERPROC, IsRenderbuffer)                           \
  X(PFNGLISFRAMEBUFFERPROC, IsFramebuffer)                             \
  X(PFNGLISBUFFERPROC, IsBuffer)                                       \
  X(PFNGLISPROGRAMPROC, IsProgram)                                     \
  X(PFNGLISSHADERPROC, IsShader)

struct GlFunctions {
#define AOVAR_GL_MEMBER(type, name) type name = nullptr;
  AOVAR_GL_FUNCTIONS(AOVAR_GL_MEMBER)
#undef AOVAR_GL_MEMBER
};

// Fills every entry ("gl" + member name). Returns the name of the first entry point OSMesa does not
// provide, or nullptr when all were found. Needs a current context.
const char* load_gl_functions(GlFunctions& gl);

}  // namespace aovar::render::osmesa
