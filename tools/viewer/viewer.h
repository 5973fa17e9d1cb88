// tools/viewer/viewer.h — `mvr view`: the interactive stereo viewer (library mvr_viewer).
//
// A GLFW window (OpenGL 3.3 core, GLX under X11) shows a stereo pair of the scene, or a row of
// N views (--views N, --view-cone, --display NAME) one at a time, as their quilt or as the
// lenticular image of a calibration (README.md, "N views"):
//  1. the pair is rendered through the mvr::Backend interface — every method of every backend of
//     the registry (mvr::backends(); the gl backend in its own EGL context, all of them on a
//     worker thread, see render_worker.h; which backend and method first: viewer_backends.h);
//  2. the HUD (at screen depth) and the 3D cursor (at the depth of the surface under the mouse)
//     are drawn into each eye's image (overlay.h, view_state.h);
//  3. the output format is composed on the CPU by mvr::composite::compose(), so the window
//     shows exactly what `mvr render --format F` writes — except anaglyphs, which by default are
//     mixed on the GPU by the same formula (composite::anaglyphGlsl(), within 1/255 of the CPU);
//     quad-buffer stereo instead puts the eyes into GL_BACK_LEFT / GL_BACK_RIGHT when the
//     driver gives a stereo visual;
//  4. the frame is uploaded as a texture and drawn 1:1 (texelFetch, no filtering; presenter.h).
// The view size follows the window: the largest views whose composite fits it, by the formats
// table's size rules (composite::largestViewSize()): one view is the window (anaglyphs,
// interleaves, half formats, quad-buffer), half of it (sbs: width, tb: height).
//
// Errors: no display or no GL context → "error: mvr view: …" and exit 3 (Unsupported); bad
// options → exit 1; unreadable models → exit 2; an unwritable screenshot → exit 4.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "mvr/composite/compose.h"
#include "options.h"

namespace mvr::viewer {

struct ViewerOptions {
    cli::SceneOptions scene;
    std::string backend;        ///< empty: defaultViewerBackend(), the first GPU backend
    std::string method;         ///< empty: the backend's start method (viewer_backends.h)
    bool backendGiven = false;  ///< --backend was on the command line (no fallback)
    std::string format = "anaglyph-dubois";
    bool formatGiven = false;  ///< --format was on the command line (else a preset's output)
    /// --quilt CxR and --lenticular-calibration visual.json (a preset fills in the rest:
    /// session::prepare(), as for `mvr render --display`).
    composite::ComposeOptions composeOptions;
    bool quiltGiven = false, calibrationGiven = false;
    bool swapEyes = false;
    std::string compose = "gpu";  ///< anaglyphs mixed on the GPU ("gpu") or the CPU ("cpu")
    int frames = 0;               ///< > 0: render this many frames, then exit
    std::string screenshot;       ///< write the last frame here (PNG)
    std::string script;           ///< --script KEYS (see input.h)
    bool noHud = false;           ///< hide HUD and cursor (for comparisons with `mvr render`)
    bool quiet = false;
};

/// The stereo output formats, from the formats table (composite::formats()): its image formats
/// of one cell grid that take two views — the seven anaglyphs, sbs, sbs-half, tb, tb-half, rows,
/// columns, checkerboard and any registerFormat() added — then quad-buffer. With a row of N > 2
/// views they show views i and i + 1.
std::vector<std::string> viewerFormats();
/// The N-view outputs: "view" (one view at a time, stepped by . and ,), "quilt" (all N views,
/// the preset's or --quilt's grid, view 0 bottom left) and "lenticular" (the panel's interleave
/// of a --lenticular-calibration). `f` cycles these first for N > 2 views, then the stereo
/// formats; after them for a stereo pair. "lenticular" only with a calibration (or when asked).
std::vector<std::string> viewerViewFormats();

/// Adds the `view` subcommand to `root`; returns the function that runs it after parsing.
std::function<int()> addViewCommand(CLI::App& root);

/// Runs the viewer until the window is closed, `q` is pressed, or `frames` frames were drawn.
/// Returns the process exit code (0, or the code of the error printed on stderr).
int runViewer(const ViewerOptions& options);

}  // namespace mvr::viewer
