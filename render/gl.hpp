// OpenGL 3.3 core entry points, loaded at run time from whoever made the context (EGL,
// OSMesa, GLFW), so that apiclab links no libGL and starts on machines without one.
// Functions are called as gl::Clear(...), which cannot collide with a system <GL/gl.h>.
#pragma once
#include <GL/glcorearb.h>

#include <string>

namespace apiclab::gl {

// X(name, type): every function the renderer uses.
#define APICLAB_GL_FUNCTIONS(X)                                              \
  X(ActiveTexture, PFNGLACTIVETEXTUREPROC)                                   \
  X(AttachShader, PFNGLATTACHSHADERPROC)                                     \
  X(BindBuffer, PFNGLBINDBUFFERPROC)                                         \
  X(BindFramebuffer, PFNGLBINDFRAMEBUFFERPROC)                               \
  X(BindRenderbuffer, PFNGLBINDRENDERBUFFERPROC)                             \
  X(BindTexture, PFNGLBINDTEXTUREPROC)                                       \
  X(BindVertexArray, PFNGLBINDVERTEXARRAYPROC)                               \
  X(BlendEquation, PFNGLBLENDEQUATIONPROC)                                   \
  X(BlendFuncSeparate, PFNGLBLENDFUNCSEPARATEPROC)                           \
  X(BlitFramebuffer, PFNGLBLITFRAMEBUFFERPROC)                               \
  X(BufferData, PFNGLBUFFERDATAPROC)                                         \
  X(CheckFramebufferStatus, PFNGLCHECKFRAMEBUFFERSTATUSPROC)                 \
  X(Clear, PFNGLCLEARPROC)                                                   \
  X(ClearColor, PFNGLCLEARCOLORPROC)                                         \
  X(CompileShader, PFNGLCOMPILESHADERPROC)                                   \
  X(CreateProgram, PFNGLCREATEPROGRAMPROC)                                   \
  X(CreateShader, PFNGLCREATESHADERPROC)                                     \
  X(DeleteBuffers, PFNGLDELETEBUFFERSPROC)                                   \
  X(DeleteFramebuffers, PFNGLDELETEFRAMEBUFFERSPROC)                         \
  X(DeleteProgram, PFNGLDELETEPROGRAMPROC)                                   \
  X(DeleteRenderbuffers, PFNGLDELETERENDERBUFFERSPROC)                       \
  X(DeleteShader, PFNGLDELETESHADERPROC)                                     \
  X(DeleteTextures, PFNGLDELETETEXTURESPROC)                                 \
  X(DeleteVertexArrays, PFNGLDELETEVERTEXARRAYSPROC)                         \
  X(DepthFunc, PFNGLDEPTHFUNCPROC)                                           \
  X(DepthMask, PFNGLDEPTHMASKPROC)                                           \
  X(Disable, PFNGLDISABLEPROC)                                               \
  X(DrawArrays, PFNGLDRAWARRAYSPROC)                                         \
  X(DrawArraysInstanced, PFNGLDRAWARRAYSINSTANCEDPROC)                       \
  X(Enable, PFNGLENABLEPROC)                                                 \
  X(EnableVertexAttribArray, PFNGLENABLEVERTEXATTRIBARRAYPROC)               \
  X(Finish, PFNGLFINISHPROC)                                                 \
  X(FramebufferRenderbuffer, PFNGLFRAMEBUFFERRENDERBUFFERPROC)               \
  X(FramebufferTexture2D, PFNGLFRAMEBUFFERTEXTURE2DPROC)                     \
  X(GenBuffers, PFNGLGENBUFFERSPROC)                                         \
  X(GenFramebuffers, PFNGLGENFRAMEBUFFERSPROC)                               \
  X(GenRenderbuffers, PFNGLGENRENDERBUFFERSPROC)                             \
  X(GenTextures, PFNGLGENTEXTURESPROC)                                       \
  X(GenVertexArrays, PFNGLGENVERTEXARRAYSPROC)                               \
  X(GetError, PFNGLGETERRORPROC)                                             \
  X(GetFloatv, PFNGLGETFLOATVPROC)                                           \
  X(GetIntegerv, PFNGLGETINTEGERVPROC)                                       \
  X(GetProgramInfoLog, PFNGLGETPROGRAMINFOLOGPROC)                           \
  X(GetProgramiv, PFNGLGETPROGRAMIVPROC)                                     \
  X(GetShaderInfoLog, PFNGLGETSHADERINFOLOGPROC)                             \
  X(GetShaderiv, PFNGLGETSHADERIVPROC)                                       \
  X(GetString, PFNGLGETSTRINGPROC)                                           \
  X(GetUniformLocation, PFNGLGETUNIFORMLOCATIONPROC)                         \
  X(LinkProgram, PFNGLLINKPROGRAMPROC)                                       \
  X(PixelStorei, PFNGLPIXELSTOREIPROC)                                       \
  X(ReadBuffer, PFNGLREADBUFFERPROC)                                         \
  X(ReadPixels, PFNGLREADPIXELSPROC)                                         \
  X(RenderbufferStorage, PFNGLRENDERBUFFERSTORAGEPROC)                       \
  X(RenderbufferStorageMultisample, PFNGLRENDERBUFFERSTORAGEMULTISAMPLEPROC) \
  X(Scissor, PFNGLSCISSORPROC)                                               \
  X(ShaderSource, PFNGLSHADERSOURCEPROC)                                     \
  X(TexImage2D, PFNGLTEXIMAGE2DPROC)                                         \
  X(TexParameteri, PFNGLTEXPARAMETERIPROC)                                   \
  X(Uniform1f, PFNGLUNIFORM1FPROC)                                           \
  X(Uniform1i, PFNGLUNIFORM1IPROC)                                           \
  X(Uniform2f, PFNGLUNIFORM2FPROC)                                           \
  X(Uniform3f, PFNGLUNIFORM3FPROC)                                           \
  X(UniformMatrix4fv, PFNGLUNIFORMMATRIX4FVPROC)                             \
  X(UseProgram, PFNGLUSEPROGRAMPROC)                                         \
  X(VertexAttribDivisor, PFNGLVERTEXATTRIBDIVISORPROC)                       \
  X(VertexAttribPointer, PFNGLVERTEXATTRIBPOINTERPROC)                       \
  X(Viewport, PFNGLVIEWPORTPROC)

#define APICLAB_GL_DECLARE(name, type) extern type name;
APICLAB_GL_FUNCTIONS(APICLAB_GL_DECLARE)
#undef APICLAB_GL_DECLARE

using ProcLoader = void* (*)(const char* name);

// Loads every function through `loader` (eglGetProcAddress, OSMesaGetProcAddress,
// glfwGetProcAddress) and checks that the current context is OpenGL 3.3 or newer.
// Returns an empty string on success, otherwise one line saying what is missing.
std::string load(ProcLoader loader);

// "llvmpipe (LLVM 15.0.6, 256 bits), OpenGL 4.5 (Core Profile) Mesa 22.3.6".
std::string describe_current_context();

}  // namespace apiclab::gl
