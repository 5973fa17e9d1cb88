#include "input.h"

#include <algorithm>
#include <charconv>

#include <fmt/core.h>

namespace mvr::viewer {

Action actionForChar(char32_t ch) {
    switch (ch) {
        case 'm': return Action::NextMethod;
        case 'M': return Action::PrevMethod;
        case 'f': return Action::NextFormat;
        case 'F': return Action::PrevFormat;
        case '+':
        case '=': return Action::SeparationUp;  // '=' is '+' without shift
        case '-':
        case '_': return Action::SeparationDown;
        case ']': return Action::ConvergenceFar;
        case '[': return Action::ConvergenceNear;
        case 'c':
        case 'C': return Action::ConvergeAtCursor;
        case 's':
        case 'S': return Action::SwapEyes;
        case 'w':
        case 'W': return Action::Wireframe;
        case 'l':
        case 'L': return Action::NextShading;
        case 'p':
        case 'P': return Action::Screenshot;
        case 'h':
        case 'H': return Action::ToggleHud;
        case '?': return Action::ToggleHelp;
        case 'r':
        case 'R': return Action::ResetView;
        case 'q':
        case 'Q': return Action::Quit;
        case '.':
        case '>': return Action::NextView;
        case ',':
        case '<': return Action::PrevView;
        case 'v':
        case 'V': return Action::ToggleView;
        case '4': return Action::HeadLeft;
        case '6': return Action::HeadRight;
        case '8': return Action::HeadUp;
        case '2': return Action::HeadDown;
        case '9': return Action::HeadNearer;
        case '3': return Action::HeadFarther;
        default: return Action::None;
    }
}

glm::vec3 headDragMm(glm::vec2 deltaPx, float screenWidthMm, int windowWidthPx) {
    const float mmPerPx = screenWidthMm / float(std::max(windowWidthPx, 1));
    return {deltaPx.x * mmPerPx, -deltaPx.y * mmPerPx, 0.0f};
}

glm::vec3 headStepMm(Action action) {
    constexpr float kStep = 20.0f;
    switch (action) {
        case Action::HeadLeft: return {-kStep, 0.0f, 0.0f};
        case Action::HeadRight: return {kStep, 0.0f, 0.0f};
        case Action::HeadUp: return {0.0f, kStep, 0.0f};
        case Action::HeadDown: return {0.0f, -kStep, 0.0f};
        case Action::HeadNearer: return {0.0f, 0.0f, -kStep};
        case Action::HeadFarther: return {0.0f, 0.0f, kStep};
        default: return glm::vec3(0.0f);
    }
}

namespace {

bool parseFloat(std::string_view text, float& out) {
    const char* end = text.data() + text.size();
    auto [ptr, ec] = std::from_chars(text.data(), end, out);
    return ec == std::errc() && ptr == end;
}

/// "NAME:A:B" → the two numbers after the prefix.
bool parsePair(std::string_view token, std::string_view prefix, float& a, float& b) {
    if (token.substr(0, prefix.size()) != prefix) return false;
    const std::string_view rest = token.substr(prefix.size());
    const std::size_t colon = rest.find(':');
    if (colon == std::string_view::npos) return false;
    return parseFloat(rest.substr(0, colon), a) && parseFloat(rest.substr(colon + 1), b);
}

}  // namespace

Result<std::vector<ScriptStep>> parseScript(std::string_view script) {
    std::vector<ScriptStep> steps;
    if (script.empty()) return steps;
    std::size_t start = 0;
    int index = 0;
    while (start <= script.size()) {
        std::size_t comma = script.find(',', start);
        if (comma == std::string_view::npos) comma = script.size();
        std::string_view token = script.substr(start, comma - start);
        while (!token.empty() && token.front() == ' ') token.remove_prefix(1);
        while (!token.empty() && token.back() == ' ') token.remove_suffix(1);
        ++index;
        ScriptStep step;
        if (token.empty()) {
            step.action = Action::None;
        } else if (token.size() == 1 && actionForChar(char32_t(token[0])) != Action::None) {
            step.action = actionForChar(char32_t(token[0]));
        } else if (token == "left") {
            step.action = Action::OrbitLeft;
        } else if (token == "right") {
            step.action = Action::OrbitRight;
        } else if (token == "up") {
            step.action = Action::OrbitUp;
        } else if (token == "down") {
            step.action = Action::OrbitDown;
        } else if (token == "pgup") {
            step.action = Action::ZoomIn;
        } else if (token == "pgdn") {
            step.action = Action::ZoomOut;
        } else if (token == "esc") {
            step.action = Action::Quit;
        } else if (token == "f1") {
            step.action = Action::ToggleHelp;
        } else if (token == "f12") {
            step.action = Action::Screenshot;
        } else if (parsePair(token, "at:", step.x, step.y)) {
            step.kind = ScriptStep::Kind::MouseAt;
        } else if (parsePair(token, "drag:", step.x, step.y)) {
            step.kind = ScriptStep::Kind::Drag;
        } else if (parsePair(token, "pan:", step.x, step.y)) {
            step.kind = ScriptStep::Kind::Pan;
        } else if (parsePair(token, "head:", step.x, step.y)) {
            step.kind = ScriptStep::Kind::Head;
        } else if (token.substr(0, 6) == "wheel:" && parseFloat(token.substr(6), step.x)) {
            step.kind = ScriptStep::Kind::Wheel;
        } else if (parsePair(token, "size:", step.x, step.y) && step.x >= 1 && step.y >= 1 &&
                   step.x <= 16384 && step.y <= 16384) {
            step.kind = ScriptStep::Kind::Resize;
        } else {
            return usageError(fmt::format(
                "--script: token {} '{}' is not a key or command (expected a key such as m, f, "
                "+, -, [, ], <, >, v, s, w, p; left, right, up, down, pgup, pgdn, esc, f1, f12; at:X:Y, "
                "drag:DX:DY, pan:DX:DY, head:DX:DY, wheel:N or size:W:H)",
                index, token));
        }
        steps.push_back(step);
        start = comma + 1;
    }
    return steps;
}

const std::vector<KeyHelp>& keyHelp() {
    static const std::vector<KeyHelp> kHelp = {
        {"mouse", "left drag: orbit, right (or shift+left) drag: pan, wheel: zoom, ctrl+left "
                  "drag: the head (--rig screen)"},
        {"m / M", "next / previous method (gl methods, then soft)"},
        {"f / F", "next / previous output format"},
        {"+ / -", "separation up / down (0.25% of screen width); view cone +/- 5 deg (N views)"},
        {"> / <",
         "next / previous view, also . and , (N views: the one shown, or the stereo pair's left)"},
        {"v", "single view on / off (N views)"},
        {"] / [", "convergence farther / nearer (x1.1)"},
        {"c", "converge at the surface under the cursor"},
        {"s", "swap eyes"},
        {"w", "wireframe on / off"},
        {"l", "shading: flat, vertex, pixel"},
        {"arrows", "orbit by 10 degrees"},
        {"4 6 8 2 9 3", "--rig screen: the head left, right, up, down, nearer, farther (20 mm)"},
        {"PgUp / PgDn", "zoom in / out"},
        {"r", "reset the view"},
        {"p, F12", "screenshot"},
        {"h", "HUD and 3D cursor on / off"},
        {"?, F1", "this help"},
        {"q, Esc", "quit"},
    };
    return kHelp;
}

}  // namespace mvr::viewer
