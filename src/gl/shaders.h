// src/gl/shaders.h — the GLSL of the gl backend (embedded at build as raw string literals in
// shaders.cpp) and the program builder. One source per stage; a method is a set of #defines.
//
// Defines (one of each group):
//   shading   SHADING_FLAT | SHADING_VERTEX | SHADING_PIXEL   (DEPTH_ONLY: no colour at all)
//   vertex    VS_DIRECT (uClipFromWorld[uView]) | VS_TO_GS | VS_INSTANCED_LAYER | VS_MULTIVIEW |
//             VS_KALAIAH
//   flat      FLAT_PROVOKING (the provoking vertex carries the face normal) when no stage
//             before the fragment shader sees the whole triangle
//   geometry  GS_VIEWS n (loop) | GS_INVOCATIONS n, and GS_OUT_LAYER | GS_OUT_VIEWPORT |
//             GS_OUT_FLAG (sorbier2008 MRT); DEPTHMAP (sorbier2008 §5.2 test)
//   multiview NUM_VIEWS n
//   maps      NORMAL_MAPS (pixel shading, a frame with a normal-mapped instance on a mesh with
//             tangents: the world tangent as a varying, location 9, 4 components more a
//             vertex; the normal map on unit 7)
//   image     ENVIRONMENT (Scene::environment: lighting.h environmentTerms — the SH in the Frame
//             block's uEnvSh, the prefiltered map on unit 8, the split sum's table on unit 9;
//             no varying, so no view limit changes)
// buildProgram() puts MAX_VIEWS (mvr::kMaxViews) and MAX_LIGHTS (mvr::kMaxLights) before the
// shared source: the sizes of the Frame block's arrays (renderer.h's FrameBlock).
#pragma once

#include <string>

#include "gl_objects.h"
#include "mvr/core/status.h"

namespace mvr::gl::detail {

struct ProgramDesc {
    std::string defines;       ///< "#define X 1\n…"
    std::string vsExtensions;  ///< "#extension …: require\n" lines for the vertex shader
    bool geometry = false;     ///< link a geometry shader
    int gsMaxVertices = 0;     ///< the geometry shader's max_vertices (0: none declared)
};

/// Appends "#define NAME VALUE\n" to d.defines.
void addDefine(ProgramDesc& d, const std::string& name, int value = 1);

/// Compiles and links. Errors: Internal with the stage's compile log or the link log.
Result<Program> buildProgram(const ProgramDesc& desc);

/// Full-screen-quad program with the fragment shader `fragmentSource` (without #version;
/// "#version 450 core" is prepended). Errors: Internal with the compile or link log.
Result<Program> buildFullScreenProgram(const std::string& fragmentSource);

/// Compute program from `source` (without #version; "#version 450 core" is prepended).
/// Errors: Internal with the compile or link log.
Result<Program> buildComputeProgram(const std::string& source);

}  // namespace mvr::gl::detail
