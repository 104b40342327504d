// capflow/render/gl: the OpenGL function table, loaded at run time from the active backend.
//
// Why: a binary that links both glvnd's libOpenGL and libOSMesa silently breaks OSMesa (its
// gl* symbols are shadowed; glGetString returns NULL). capflow_render therefore links NO GL
// library at all: libEGL.so.1 and libOSMesa.so.8 are dlopen()ed by context.cpp, and every GL
// entry point below is a pointer filled by load_gl_functions() from eglGetProcAddress or
// OSMesaGetProcAddress once a context is current.
//
// Usage: include this header (never <GL/gl.h>) and call glXxx(...) as usual; the names resolve
// to capflow::glfn::glXxx pointers through the using-directive at the bottom. Dear ImGui's
// OpenGL3 backend is compiled with this header force-included (IMGUI_IMPL_OPENGL_LOADER_CUSTOM).
//
// Contract: the table is process-wide. Loading it again for the same backend yields the same
// pointers (they are dispatch stubs), so several contexts of ONE backend may live in different
// threads; contexts of DIFFERENT backends must not be used at the same time in one process.
#pragma once

#include <GL/glcorearb.h>  // types, enums and PFN typedefs only (no prototypes)

#include "render/gl_functions.inc"

namespace capflow::glfn {
#define CAPFLOW_GL_DECLARE(type, name) extern type name;
CAPFLOW_GL_FUNCTIONS(CAPFLOW_GL_DECLARE)
#undef CAPFLOW_GL_DECLARE

using ProcLoader = void* (*)(const char* name, void* user);
// Fills every pointer through `loader`. Returns false and names the first missing function in
// *missing if one cannot be resolved.
bool load_gl_functions(ProcLoader loader, void* user, const char** missing);
}  // namespace capflow::glfn

using namespace capflow::glfn;  // NOLINT: GL names must resolve unqualified (ImGui backend)
