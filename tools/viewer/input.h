// tools/viewer/input.h — what a key press or a scripted step does in `mvr view`.
//
// Keys and --script tokens map to the same actions, so a script replays exactly what a person
// would type. Script syntax: tokens separated by commas, applied one per frame in order:
//   a single character     that key ("m", "+", "[", "?", ">", "<"; see keyHelp())
//   left right up down     arrow keys (orbit by 10°);  pgup pgdn: zoom;  esc: quit
//   f1 f12                 help, screenshot
//   (empty)                a frame with no input (",," or a trailing ",")
//   at:X:Y                 put the mouse at window pixel (X, Y) (row 0 at the top)
//   drag:DX:DY             a left-button drag by (DX, DY) window pixels (orbit)
//   pan:DX:DY              a right-button drag (pan)
//   wheel:N                N wheel steps (positive: zoom in)
//   size:W:H               resize the window to W×H (screen coordinates)
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>

#include "mvr/core/status.h"

namespace mvr::viewer {

enum class Action {
    None,
    NextMethod,
    PrevMethod,  // m M
    NextFormat,
    PrevFormat,  // f F
    SeparationUp,
    SeparationDown,  // + -
    ConvergenceFar,
    ConvergenceNear,   // ] [
    ConvergeAtCursor,  // c
    SwapEyes,          // s
    Wireframe,         // w
    NextShading,       // l
    Screenshot,        // p, F12
    ToggleHud,         // h
    ToggleHelp,        // ?, F1
    ResetView,         // r
    OrbitLeft,
    OrbitRight,
    OrbitUp,
    OrbitDown,  // arrows
    ZoomIn,
    ZoomOut,  // PgUp PgDn (also the wheel)
    Quit,     // q, Esc
    // Rows of N views (appended): step through the views, single view on / off.
    NextView,    // . >
    PrevView,    // , <  (',' separates script steps: scripts use '<')
    ToggleView,  // v
    // --rig screen (appended): move the head, both eyes, 20 mm (numeric keypad's directions).
    HeadLeft,     // 4
    HeadRight,    // 6
    HeadUp,       // 8
    HeadDown,     // 2
    HeadNearer,   // 9 (toward the screen)
    HeadFarther,  // 3
};

/// How far a Head* action moves the eyes, mm of screen space (x right, y up, z toward the
/// viewer); zero for other actions.
glm::vec3 headStepMm(Action action);

/// What a mouse drag does: orbit (left), pan (right, middle, shift+left), or, with --rig screen,
/// move the head (ctrl+left) in the screen's plane, the window's width standing for the
/// screen's: a drag across the whole window moves the head by the screen's width.
enum class DragMode { None, Orbit, Pan, Head };

/// How far a head drag of `deltaPx` (window pixels, y down) moves the head, mm of screen space.
glm::vec3 headDragMm(glm::vec2 deltaPx, float screenWidthMm, int windowWidthPx);

/// The action of a printable key (its character as typed), or Action::None.
Action actionForChar(char32_t ch);

/// One scripted step.
struct ScriptStep {
    enum class Kind { Action, MouseAt, Drag, Pan, Head, Wheel, Resize } kind = Kind::Action;
    Action action = Action::None;
    float x = 0.0f,
          y = 0.0f;  ///< MouseAt: position; Drag/Pan/Head: delta; Wheel: steps in x; Resize: size
};

/// Parses a --script string. Errors (ErrorCode::Usage): an unknown token, naming it and its
/// position ("--script: token 3 'zz' is not a key or command (expected …)").
Result<std::vector<ScriptStep>> parseScript(std::string_view script);

/// One line of the key list: the keys and what they do.
struct KeyHelp {
    std::string keys;
    std::string what;
};

/// The key list for --help and the window's help overlay.
const std::vector<KeyHelp>& keyHelp();

}  // namespace mvr::viewer
