#include "viewer.h"
#include "viewer_window.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <epoxy/gl.h>
#define GLFW_INCLUDE_NONE
#include <GLFW/glfw3.h>
#include <fmt/core.h>
#include <fmt/format.h>

#include "input.h"
#include "mvr/backends.h"
#include "mvr/composite/anaglyph.h"
#include "mvr/composite/compose.h"
#include "mvr/composite/lenticular.h"
#include "mvr/io/png.h"
#include "overlay.h"
#include "presenter.h"
#include "render_worker.h"
#include "view_state.h"
#include "viewer_backends.h"

namespace mvr::viewer {

namespace {

using Clock = std::chrono::steady_clock;
constexpr std::string_view kQuadBuffer = "quad-buffer";
constexpr std::string_view kQuadBufferFallback = "anaglyph-dubois";
constexpr std::string_view kSingleView = "view";

/// Formats that show all N views (the rest show one view or a stereo pair).
bool allViews(std::string_view format) { return format == "quilt" || format == "lenticular"; }

double msSince(Clock::time_point t) {
    return std::chrono::duration<double, std::milli>(Clock::now() - t).count();
}

// ---- geometry of the output formats: the composite formats table's size rules ---------------
// quad-buffer is no composite format: each eye is the window.

/// The size rule of `format` (one cell, the view's size, for quad-buffer).
composite::FormatSize sizeRule(const std::string& format) {
    Result<composite::FormatInfo> info = composite::findFormat(format);
    return info ? info->size : composite::FormatSize{};
}

/// A position in the composed frame → the position in one view that it shows (the mouse's
/// position "on the screen", before any eye offset): within its cell, unsqueezed.
glm::vec2 viewPxFromFrame(const std::string& format, glm::vec2 p, glm::ivec2 view) {
    const composite::FormatSize rule = sizeRule(format);
    if (rule.rule != composite::SizeRule::Tiled) return p;
    const float cellW = float(view.x) / float(rule.squeezeX);
    const float cellH = float(view.y) / float(rule.squeezeY);
    return {std::fmod(p.x, cellW) * float(rule.squeezeX),
            std::fmod(p.y, cellH) * float(rule.squeezeY)};
}

// ---- GLFW errors -------------------------------------------------------------------------------

std::string& lastGlfwError() {
    static std::string error;
    return error;
}

void onGlfwError(int code, const char* description) {
    lastGlfwError() = fmt::format("{} (GLFW error 0x{:x})", description ? description : "?", code);
}

// ---- the viewer --------------------------------------------------------------------------------

class Viewer {
public:
    Viewer(const ViewerOptions& options, session::Prepared prepared, std::vector<ScriptStep> script)
        : mOptions(options),
          mPrepared(std::move(prepared)),
          mScript(std::move(script)),
          mSettings(mPrepared.settings),
          mStereo(StereoCamera::fromRig(mPrepared.rig, mPrepared.scene.bounds().radius(),
                                        mPrepared.viewConeDegrees)),
          mInitialStereo(mStereo),
          mSwapEyes(options.swapEyes),
          mShowHud(!options.noHud),
          mCompose(options.composeOptions) {
        mSettings.depth = true;  // the viewer reads view 0's depth (parallax line, 3D cursor)
    }

    int run();

private:
    // Setup and teardown.
    Status openWindow(glm::ivec2 size);
    void shutdown();

    // Per frame.
    Status renderFrame();
    Status composeAndPresent();
    void present();
    Status writeScreenshot(const std::filesystem::path& path);
    std::filesystem::path nextScreenshotPath();

    // Input.
    void apply(Action action);
    void applyStep(const ScriptStep& step);
    void cycleMethod(int direction);
    void cycleFormat(int direction);
    void say(std::string message);
    void drag(glm::vec2 delta, DragMode mode);

    std::string formatName() const { return mFormats[mFormatIndex]; }
    int viewCount() const { return mStereo.columns; }
    /// The views the stereo formats show: the current view and the next (0 and 1 for a pair).
    std::pair<int, int> pairViews() const {
        const int a = std::clamp(mViewIndex, 0, std::max(0, viewCount() - 2));
        return {a, std::min(a + 1, viewCount() - 1)};
    }
    glm::ivec2 viewSizeFor(const std::string& format, glm::ivec2 fb) const;
    glm::ivec2 frameSizeFor(const std::string& format, glm::ivec2 view) const;
    void stepView(int direction);
    bool quadBuffer() const { return formatName() == kQuadBuffer; }
    const MethodRef& method() const { return mBackends.methods()[mMethodIndex]; }
    void drawOverlays(std::vector<Image>& views);
    std::vector<std::string> hudLines() const;

    const ViewerOptions& mOptions;
    session::Prepared mPrepared;
    std::vector<ScriptStep> mScript;
    std::size_t mScriptNext = 0;

    RenderWorker mWorker;
    ViewerBackends mBackends;  // touched on mWorker only
    std::size_t mMethodIndex = 0;
    std::size_t mFormatIndex = 0;
    std::vector<std::string> mFormats;  ///< what f cycles (viewerFormats(), viewerViewFormats())
    std::size_t mFormatBeforeView = 0;  ///< v returns to it
    int mViewIndex = 0;                 ///< the view shown ("view"), the pair's left (stereo)

    RenderSettings mSettings;
    StereoCamera mStereo;
    StereoCamera mInitialStereo;
    bool mSwapEyes = false;
    bool mShowHud = true;
    bool mShowHelp = false;
    composite::ComposeOptions mCompose;  ///< quilt grid and aspect, lenticular calibration

    GLFWwindow* mWindow = nullptr;
    bool mStereoWindow = false;
    /// The anaglyph being mixed on the GPU this frame (textures 0 and 1 hold the eyes); nullopt:
    /// texture 0 holds the composed frame (or the left eye for quad-buffer).
    std::optional<composite::AnaglyphMethod> mGpuAnaglyph;
    std::unique_ptr<Presenter> mPresenter;
    glm::ivec2 mFb{0};

    // The last rendered frame.
    std::optional<Rig> mRig;
    RenderOutput mOutput;
    std::optional<ParallaxRange> mParallax;
    CursorPlacement mCursor;
    bool mCursorShown = false;
    double mRenderMs = 0.0, mComposeMs = 0.0, mFrameMs = 0.0;
    struct Timing {
        double frameMs = 0, renderMs = 0, composeMs = 0;
    } mShownTiming;  ///< the last completed frame's, for the HUD
    bool mNeedRender = true;

    // Mouse.
    glm::dvec2 mMouse{0.0};  ///< window coordinates, row 0 at the top
    bool mMouseInside = false;
    bool mMouseScripted = false;  ///< a script step placed the mouse: ignore the real pointer
    DragMode mDragging = DragMode::None;
    glm::dvec2 mDragFrom{0.0};

    std::string mMessage;
    Clock::time_point mMessageUntil{};
    const Clock::time_point mStarted = Clock::now();
    bool mGpuAnaglyphFailed = false;
    bool mScreenshotRequested = false;
    int mScreenshotCount = 0;
    bool mQuit = false;
    long mFrames = 0;
};

Status Viewer::openWindow(glm::ivec2 size) {
    glfwSetErrorCallback(onGlfwError);
    if (!glfwInit()) {
        return unsupportedError(fmt::format(
            "mvr view: cannot open a window: {} (the viewer needs a display: set DISPLAY, or run "
            "it under xvfb-run)",
            lastGlfwError().empty() ? "glfwInit() failed" : lastGlfwError()));
    }
    auto hints = [](bool stereo) {
        glfwDefaultWindowHints();
        glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
        glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
        glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
        glfwWindowHint(GLFW_OPENGL_FORWARD_COMPAT, GLFW_TRUE);
        glfwWindowHint(GLFW_DEPTH_BITS, 0);
        glfwWindowHint(GLFW_STEREO, stereo ? GLFW_TRUE : GLFW_FALSE);
    };
    // A frame larger than the desktop (a 3360x3360 quilt) opens scaled down to fit it, keeping
    // its aspect: the views then follow the window, as after a resize.
    int ax = 0, ay = 0, aw = 0, ah = 0;
    if (GLFWmonitor* monitor = glfwGetPrimaryMonitor())
        glfwGetMonitorWorkarea(monitor, &ax, &ay, &aw, &ah);
    if (aw > 0 && ah > 0 && (size.x > aw || size.y > ah)) {
        const float s = std::min(float(aw) / float(size.x), float(ah) / float(size.y));
        const glm::ivec2 fitted = glm::max(glm::ivec2(glm::vec2(size) * s), glm::ivec2(2));
        if (!mOptions.quiet) {
            fmt::print("mvr view: a {}x{} frame is larger than the desktop ({}x{}): window {}x{}\n",
                       size.x, size.y, aw, ah, fitted.x, fitted.y);
        }
        size = fitted;
    }
    const std::string title = fmt::format("mvr view — {}", mPrepared.sceneName);
    // Quad-buffer stereo needs a stereo visual, which only some drivers give (NVIDIA Quadro,
    // AMD FirePro with stereo enabled): ask for one first, fall back to a mono window.
    hints(true);
    mWindow = glfwCreateWindow(size.x, size.y, title.c_str(), nullptr, nullptr);
    mStereoWindow = mWindow != nullptr;
    if (!mWindow) {
        hints(false);
        mWindow = glfwCreateWindow(size.x, size.y, title.c_str(), nullptr, nullptr);
    }
    if (!mWindow) {
        return unsupportedError(
            fmt::format("mvr view: cannot create an OpenGL 3.3 core window: {}", lastGlfwError()));
    }
    glfwMakeContextCurrent(mWindow);
    if (epoxy_gl_version() < 33) {
        return unsupportedError(
            fmt::format("mvr view: the window's OpenGL is {}.{} (expected 3.3 core)",
                        epoxy_gl_version() / 10, epoxy_gl_version() % 10));
    }
    glfwSwapInterval(mOptions.frames > 0 ? 0 : 1);
    mPresenter = std::make_unique<Presenter>();
    if (Status s = mPresenter->init(); !s) return s;

    glfwSetWindowUserPointer(mWindow, this);
    glfwSetCharCallback(mWindow, [](GLFWwindow* w, unsigned int ch) {
        auto* self = static_cast<Viewer*>(glfwGetWindowUserPointer(w));
        self->apply(actionForChar(char32_t(ch)));
    });
    glfwSetKeyCallback(mWindow, [](GLFWwindow* w, int key, int, int action, int) {
        if (action == GLFW_RELEASE) return;
        auto* self = static_cast<Viewer*>(glfwGetWindowUserPointer(w));
        switch (key) {
            case GLFW_KEY_LEFT: self->apply(Action::OrbitLeft); break;
            case GLFW_KEY_RIGHT: self->apply(Action::OrbitRight); break;
            case GLFW_KEY_UP: self->apply(Action::OrbitUp); break;
            case GLFW_KEY_DOWN: self->apply(Action::OrbitDown); break;
            case GLFW_KEY_PAGE_UP: self->apply(Action::ZoomIn); break;
            case GLFW_KEY_PAGE_DOWN: self->apply(Action::ZoomOut); break;
            case GLFW_KEY_ESCAPE: self->apply(Action::Quit); break;
            case GLFW_KEY_F1: self->apply(Action::ToggleHelp); break;
            case GLFW_KEY_F12: self->apply(Action::Screenshot); break;
            default: break;
        }
    });
    glfwSetCursorPosCallback(mWindow, [](GLFWwindow* w, double x, double y) {
        auto* self = static_cast<Viewer*>(glfwGetWindowUserPointer(w));
        const glm::dvec2 p(x, y);
        if (self->mDragging != DragMode::None) {
            self->drag(glm::vec2(p - self->mDragFrom), self->mDragging);
            self->mDragFrom = p;
        }
        self->mMouse = p;
    });
    glfwSetMouseButtonCallback(mWindow, [](GLFWwindow* w, int button, int action, int mods) {
        auto* self = static_cast<Viewer*>(glfwGetWindowUserPointer(w));
        double x = 0, y = 0;
        glfwGetCursorPos(w, &x, &y);
        self->mDragFrom = {x, y};
        const bool left = button == GLFW_MOUSE_BUTTON_LEFT;
        self->mDragging = action != GLFW_PRESS             ? DragMode::None
                          : left && (mods & GLFW_MOD_CONTROL) ? DragMode::Head
                          : left && !(mods & GLFW_MOD_SHIFT)  ? DragMode::Orbit
                                                              : DragMode::Pan;
    });
    glfwSetScrollCallback(mWindow, [](GLFWwindow* w, double, double dy) {
        auto* self = static_cast<Viewer*>(glfwGetWindowUserPointer(w));
        self->mStereo.zoom(std::pow(0.9f, float(dy)));
        self->mNeedRender = true;
    });
    // The 3D cursor replaces the system one over the window (nvidia-gtc2010: "can not use the HW
    // cursor" in stereo: it would sit at screen depth, in front of or inside the surface).
    if (mShowHud) glfwSetInputMode(mWindow, GLFW_CURSOR, GLFW_CURSOR_HIDDEN);
    return Status::ok();
}

void Viewer::shutdown() {
    mWorker.call([this] { mBackends.clear(); });  // GL objects die with their EGL context's thread
    if (mWindow) {
        glfwMakeContextCurrent(mWindow);
        mPresenter.reset();
        glfwDestroyWindow(mWindow);
        mWindow = nullptr;
    }
    glfwTerminate();
}

void Viewer::say(std::string message) {
    if (!mOptions.quiet) fmt::print("mvr view: {}\n", message);
    std::fflush(stdout);
    mMessage = std::move(message);
    mMessageUntil = Clock::now() + std::chrono::seconds(4);
}

void Viewer::drag(glm::vec2 delta, DragMode mode) {
    int w = 1, h = 1;
    glfwGetWindowSize(mWindow, &w, &h);
    if (mode == DragMode::Head) {
        if (!mStereo.moveHead(headDragMm(delta, mStereo.screenWidthMm(), w)))
            return say("head not moved: --rig screen only, the eyes in front of the screen");
    } else if (mode == DragMode::Pan) {
        mStereo.pan(-delta.x / float(std::max(h, 1)), delta.y / float(std::max(h, 1)));
    } else {
        mStereo.orbit(-delta.x * 0.006f, delta.y * 0.006f);
    }
    mNeedRender = true;
}

void Viewer::cycleMethod(int direction) {
    const std::size_t n = mBackends.methods().size();
    std::vector<std::string> skipped;
    std::size_t index = mMethodIndex;
    for (std::size_t tries = 0; tries + 1 < n; ++tries) {
        index = (index + n + std::size_t(direction + int(n))) % n;
        const MethodRef ref = mBackends.methods()[index];
        Status s = mWorker.call(
            [this, ref] { return mBackends.backend(ref.backend).supports(ref.method); });
        if (s) {
            mMethodIndex = index;
            mNeedRender = true;
            say(fmt::format("method {}{}", ref.label(),
                            skipped.empty()
                                ? ""
                                : " (skipped, unsupported here: " +
                                      fmt::format("{}", fmt::join(skipped, ", ")) + ")"));
            return;
        }
        skipped.push_back(ref.label());
    }
    say(fmt::format("method {}: no other method is supported here", method().label()));
}

glm::ivec2 Viewer::viewSizeFor(const std::string& format, glm::ivec2 fb) const {
    if (format.empty() || format == kSingleView) return glm::max(fb, glm::ivec2(2));
    // The lenticular image is the panel's (or the views' own size): the views keep their size.
    if (format == "lenticular") return {mSettings.width, mSettings.height};
    Result<composite::Size> v = composite::largestViewSize(
        format, allViews(format) ? viewCount() : 2, fb.x, fb.y, mCompose);
    return glm::max(v ? glm::ivec2(v->width, v->height) : fb, glm::ivec2(2));
}

glm::ivec2 Viewer::frameSizeFor(const std::string& format, glm::ivec2 view) const {
    if (format.empty() || format == kSingleView) return view;
    Result<composite::Size> f =
        composite::outputSize(format, allViews(format) ? viewCount() : 2, view.x, view.y, mCompose);
    return f ? glm::ivec2(f->width, f->height) : view;
}

void Viewer::stepView(int direction) {
    const int n = viewCount();
    mViewIndex = ((mViewIndex + direction) % n + n) % n;
    if (formatName() == kSingleView || allViews(formatName())) {
        say(fmt::format("view {} of {} (0 = leftmost)", mViewIndex, n));
    } else {
        const auto [a, b] = pairViews();
        say(fmt::format("views {} and {} of {} (the stereo pair)", a, b, n));
    }
}

void Viewer::cycleFormat(int direction) {
    const std::size_t n = mFormats.size();
    mFormatIndex = (mFormatIndex + n + std::size_t(direction + int(n))) % n;
    if (quadBuffer() && !mStereoWindow) {
        say("quad-buffer: the driver gives no stereo visual (GLFW_STEREO); skipped");
        mFormatIndex = (mFormatIndex + n + std::size_t(direction + int(n))) % n;
    }
    say(fmt::format("output {}", formatName()));
}

void Viewer::apply(Action action) {
    switch (action) {
        case Action::None: return;
        case Action::NextMethod: cycleMethod(+1); return;
        case Action::PrevMethod: cycleMethod(-1); return;
        case Action::NextFormat: cycleFormat(+1); return;
        case Action::PrevFormat: cycleFormat(-1); return;
        case Action::SeparationUp:
        case Action::SeparationDown: {
            if (mStereo.viewConeDegrees > 0.0f) {  // a view-cone rig: + / - change the cone
                mStereo.setViewCone(mStereo.viewConeDegrees +
                                    (action == Action::SeparationUp ? 5.0f : -5.0f));
                mNeedRender = true;
                say(fmt::format("view cone {:g} degrees", mStereo.viewConeDegrees));
                return;
            }
            const float step = action == Action::SeparationUp ? 0.0025f : -0.0025f;
            mStereo.setSeparation(mStereo.separation() + step);
            mNeedRender = true;
            say(fmt::format("separation {:.2f}% of screen width", 100.0 * mStereo.separation()));
            return;
        }
        case Action::ConvergenceFar:
        case Action::ConvergenceNear:
            mStereo.setConvergence(mStereo.convergence *
                                   (action == Action::ConvergenceFar ? 1.1f : 1.0f / 1.1f));
            mNeedRender = true;
            say(fmt::format("convergence {:.4g}", mStereo.convergence));
            return;
        case Action::ConvergeAtCursor:
            if (mCursorShown && mCursor.onSurface) {
                mStereo.setConvergence(mCursor.distance);
                mNeedRender = true;
                say(fmt::format("convergence {:.4g} (the surface under the cursor)",
                                mStereo.convergence));
            } else {
                say("converge at cursor: no surface under the cursor");
            }
            return;
        case Action::SwapEyes:
            mSwapEyes = !mSwapEyes;
            say(mSwapEyes ? "eyes swapped" : "eyes not swapped");
            return;
        case Action::Wireframe:
            mSettings.wireframe = !mSettings.wireframe;
            mNeedRender = true;
            say(mSettings.wireframe ? "wireframe on" : "wireframe off");
            return;
        case Action::NextShading:
            if (mSettings.specular == SpecularEye::PerView) {
                // Per-view highlights are per pixel (shadedSettings): nothing to cycle.
                say("pixel shading (--specular per-view)");
                return;
            }
            mSettings.shading = mSettings.shading == Shading::Flat     ? Shading::Vertex
                                : mSettings.shading == Shading::Vertex ? Shading::Pixel
                                                                       : Shading::Flat;
            mNeedRender = true;
            say(fmt::format("{} shading", shadingName(mSettings.shading)));
            return;
        case Action::Screenshot: mScreenshotRequested = true; return;
        case Action::ToggleHud:
            mShowHud = !mShowHud;
            glfwSetInputMode(mWindow, GLFW_CURSOR,
                             mShowHud ? GLFW_CURSOR_HIDDEN : GLFW_CURSOR_NORMAL);
            return;
        case Action::ToggleHelp: mShowHelp = !mShowHelp; return;
        case Action::ResetView: {
            const float aspect = mStereo.camera.aspect;
            mStereo = mInitialStereo;
            mStereo.setAspect(aspect);
            mNeedRender = true;
            say("view reset");
            return;
        }
        case Action::OrbitLeft: mStereo.orbit(glm::radians(-10.0f), 0.0f); break;
        case Action::OrbitRight: mStereo.orbit(glm::radians(10.0f), 0.0f); break;
        case Action::OrbitUp: mStereo.orbit(0.0f, glm::radians(10.0f)); break;
        case Action::OrbitDown: mStereo.orbit(0.0f, glm::radians(-10.0f)); break;
        case Action::ZoomIn: mStereo.zoom(1.0f / 1.15f); break;
        case Action::ZoomOut: mStereo.zoom(1.15f); break;
        case Action::Quit: mQuit = true; return;
        case Action::NextView: stepView(+1); return;
        case Action::PrevView: stepView(-1); return;
        case Action::ToggleView: {
            if (formatName() == kSingleView) {
                mFormatIndex = mFormatBeforeView;
            } else {
                mFormatBeforeView = mFormatIndex;
                mFormatIndex = std::size_t(
                    std::find(mFormats.begin(), mFormats.end(), kSingleView) - mFormats.begin());
            }
            say(fmt::format("output {}", formatName()));
            return;
        }
        case Action::HeadLeft: case Action::HeadRight: case Action::HeadUp: case Action::HeadDown:
        case Action::HeadNearer: case Action::HeadFarther:  // --rig screen: the eyes in front
            if (!mStereo.moveHead(headStepMm(action)))
                return say("head not moved: --rig screen only, the eyes in front of the screen");
            break;
    }
    mNeedRender = true;  // orbit / zoom / head
}

void Viewer::applyStep(const ScriptStep& step) {
    switch (step.kind) {
        case ScriptStep::Kind::Action: apply(step.action); break;
        case ScriptStep::Kind::MouseAt:
            mMouse = {step.x, step.y};
            mMouseInside = true;
            mMouseScripted = true;
            break;
        case ScriptStep::Kind::Drag: drag({step.x, step.y}, DragMode::Orbit); break;
        case ScriptStep::Kind::Pan: drag({step.x, step.y}, DragMode::Pan); break;
        case ScriptStep::Kind::Head: drag({step.x, step.y}, DragMode::Head); break;
        case ScriptStep::Kind::Wheel:
            mStereo.zoom(std::pow(0.9f, step.x));
            mNeedRender = true;
            break;
        case ScriptStep::Kind::Resize:
            glfwSetWindowSize(mWindow, int(step.x), int(step.y));
            glfwPollEvents();
            break;
    }
}

Status Viewer::renderFrame() {
    auto rig = mStereo.rig();
    if (!rig) return rig.status();
    const MethodRef ref = method();
    const auto start = Clock::now();
    Result<RenderOutput> out = mWorker.call([&]() {
        return mBackends.backend(ref.backend).render(mPrepared.scene, *rig, mSettings, ref.method);
    });
    mRenderMs = msSince(start);
    if (!out) return out.status();
    if (out->color.size() != std::size_t(rig->viewCount())) {
        return internalError(fmt::format("{} returned {} images for {} views", ref.label(),
                                         out->color.size(), rig->viewCount()));
    }
    mOutput = std::move(out).value();
    mRig = std::move(rig).value();
    mParallax.reset();
    if (!mOutput.depth.empty()) mParallax = frameParallaxRange(*mRig, mOutput.depth[0]);
    mNeedRender = false;
    return Status::ok();
}

std::vector<std::string> Viewer::hudLines() const {
    std::vector<std::string> lines;
    const MethodRef& ref = method();
    std::string methodText = ref.label();
    if (!mOutput.method.empty() && mOutput.method != ref.method)
        methodText += " -> " + mOutput.method;
    const Timing& t = mShownTiming;
    lines.push_back(fmt::format("{:.1f} fps ({:.0f} ms: render {:.0f}, compose {:.0f})  {}  {}{}",
                                t.frameMs > 0 ? 1000.0 / t.frameMs : 0.0, t.frameMs, t.renderMs,
                                t.composeMs, methodText, formatName(),
                                mSwapEyes ? " (eyes swapped)" : ""));
    lines.push_back(fmt::format("separation {:.2f}%  convergence {:.4g}  interaxial {:.4g}  {}{}",
                                100.0 * mStereo.separation(), mStereo.convergence,
                                mStereo.interaxial, shadingName(mSettings.shading),
                                mSettings.wireframe ? " wireframe" : ""));
    if (viewCount() > 2 || formatName() == kSingleView || allViews(formatName())) {
        const std::string cone = mStereo.viewConeDegrees > 0.0f
                                     ? fmt::format("view cone {:g} deg", mStereo.viewConeDegrees)
                                     : std::string("no view cone (interaxial spacing)");
        const auto [a, b] = pairViews();
        const std::string shown =
            formatName() == kSingleView ? fmt::format("view {} of {}", mViewIndex, viewCount())
            : allViews(formatName())
                ? fmt::format("all {} views (current {})", viewCount(), mViewIndex)
                : fmt::format("views {},{} of {}", a, b, viewCount());
        lines.push_back(
            fmt::format("{}  {}  {}x{} per view", shown, cone, mSettings.width, mSettings.height));
    }
    if (mParallax) {
        lines.push_back(fmt::format("parallax {:+.2f}% .. {:+.2f}% of screen width: {}",
                                    100.0 * mParallax->minParallax, 100.0 * mParallax->maxParallax,
                                    mParallax->comfortable ? "comfortable" : "UNCOMFORTABLE"));
    } else {
        lines.push_back(mOutput.depth.empty()
                            ? fmt::format("parallax: n/a ({} gives no depth image)", ref.method)
                            : std::string("parallax: n/a (nothing drawn)"));
    }
    if (mCursorShown) {
        lines.push_back(mCursor.onSurface
                            ? fmt::format("cursor: distance {:.4g}, parallax {:+.2f}%",
                                          mCursor.distance, 100.0 * mCursor.parallax)
                            : std::string("cursor: no surface (at screen depth)"));
    }
    lines.push_back(mShowHelp ? "" : "? help");
    return lines;
}

void Viewer::drawOverlays(std::vector<Image>& views) {
    const int width = views[0].width, height = views[0].height;
    // The HUD: the same pixels in both eyes = zero parallax = on the screen plane.
    const int scale = height >= 600 ? 2 : 1;
    const Rgba8 text{240, 240, 240, 255};
    std::string block;
    for (const std::string& line : hudLines()) block += line + "\n";
    // The key help (?) below the status lines, in two aligned columns.
    std::string keys, what;
    if (mShowHelp) {
        for (const KeyHelp& k : keyHelp()) {
            keys += k.keys + "\n";
            what += k.what + "\n";
        }
    }
    const int margin = 4 * scale;
    const glm::ivec2 status = textSize(block, scale);
    const int keysWidth = textSize(keys, scale).x + 3 * margin;
    const glm::ivec2 help(keysWidth + textSize(what, scale).x, textSize(keys, scale).y);
    const glm::ivec2 size(std::max(status.x, help.x), status.y + help.y);
    for (Image& view : views) {
        darkenRect(view, 0, 0, size.x + 2 * margin, size.y + 2 * margin, 0.35f);
        drawText(view, margin, margin, block, text, scale);
        drawText(view, margin, margin + status.y, keys, text, scale);
        drawText(view, margin + keysWidth, margin + status.y, what, text, scale);
    }
    if (!mMessage.empty() && Clock::now() < mMessageUntil) {
        const glm::ivec2 m = textSize(mMessage, scale);
        for (Image& view : views) {
            darkenRect(view, 0, height - m.y - 2 * margin, m.x + 2 * margin, height, 0.35f);
            drawText(view, margin, height - m.y - margin, mMessage, text, scale);
        }
    }
    // The 3D cursor: each eye gets it where its 3D point projects in that eye.
    if (mCursorShown) {
        const int arm = std::max(8, std::min(width, height) / 40);
        for (int v = 0; v < 2 && v < int(views.size()); ++v) {
            drawCrosshair(views[std::size_t(v)], mCursor.viewPx[v], arm, text);
        }
    }
}

Status Viewer::composeAndPresent() {
    const std::string format = quadBuffer() ? std::string(kQuadBufferFallback) : formatName();
    const glm::ivec2 view(mSettings.width, mSettings.height);
    const bool stereo = format != kSingleView && !allViews(format);
    // The mouse, in one view's pixels ("on the screen"), for the 3D cursor (a stereo pair's).
    mCursorShown = false;
    int ww = 1, wh = 1;
    glfwGetWindowSize(mWindow, &ww, &wh);
    if (!mMouseScripted) {
        // The pointer, polled: enter/move events do not come for a pointer that was already
        // over the window when it opened.
        glfwGetCursorPos(mWindow, &mMouse.x, &mMouse.y);
        mMouseInside = mMouse.x >= 0 && mMouse.y >= 0 && mMouse.x < ww && mMouse.y < wh;
    }
    if (mShowHud && mMouseInside && mRig && stereo && viewCount() == 2) {
        const glm::vec2 fbPx =
            glm::vec2(mMouse) * glm::vec2(mFb) / glm::vec2(std::max(ww, 1), std::max(wh, 1));
        const glm::ivec2 frame = quadBuffer() ? view : frameSizeFor(format, view);
        const glm::vec2 framePx = fbPx - glm::vec2((mFb - frame) / 2);
        if (framePx.x >= 0 && framePx.y >= 0 && framePx.x < frame.x && framePx.y < frame.y) {
            const DepthImage none;
            mCursor = placeCursor(*mRig, mOutput.depth.empty() ? none : mOutput.depth[0],
                                  viewPxFromFrame(quadBuffer() ? "" : format, framePx, view),
                                  view.x, view.y);
            mCursorShown = true;
        }
    }
    const auto start = Clock::now();
    glClearColor(0.0f, 0.0f, 0.0f, 1.0f);
    mGpuAnaglyph.reset();
    if (format == kSingleView) {
        // One view, 1:1; the HUD drawn into it.
        std::vector<Image> one = {mOutput.color[std::size_t(mViewIndex)]};
        if (mShowHud) drawOverlays(one);
        mPresenter->upload(0, one[0]);
    } else if (allViews(format)) {
        composite::ComposeOptions options = mCompose;
        options.swapEyes = mSwapEyes;
        Result<Image> frame = Image();
        if (format == "lenticular" && mShowHud) {
            // Into every view at the same pixels: zero parallax, on the panel's surface.
            std::vector<Image> views = mOutput.color;
            drawOverlays(views);
            frame = composite::compose(format, views, options);
        } else {
            frame = composite::compose(format, mOutput.color, options);
        }
        if (!frame) return frame.status();
        if (format == "quilt" && mShowHud) {
            // The quilt is a flat picture of all the views: the HUD goes on top of it.
            std::vector<Image> whole = {std::move(frame).value()};
            drawOverlays(whole);
            mPresenter->upload(0, whole[0]);
        } else {
            mPresenter->upload(0, *frame);
        }
    } else {
        const auto [a, b] = pairViews();
        std::vector<Image> views = {mOutput.color[std::size_t(a)], mOutput.color[std::size_t(b)]};
        if (mShowHud) drawOverlays(views);
        const std::optional<composite::AnaglyphMethod> anaglyph = composite::anaglyphMethod(format);
        if (quadBuffer() || (anaglyph && mOptions.compose == "gpu" && !mGpuAnaglyphFailed)) {
            mPresenter->upload(0, views[mSwapEyes ? 1 : 0]);
            mPresenter->upload(1, views[mSwapEyes ? 0 : 1]);
            if (!quadBuffer()) mGpuAnaglyph = anaglyph;
        } else {
            composite::ComposeOptions options;
            options.swapEyes = mSwapEyes;
            auto frame = composite::compose(format, views, options);
            if (!frame) return frame.status();
            mPresenter->upload(0, *frame);
        }
    }
    mComposeMs = msSince(start);  // HUD + cursor + format + upload
    present();
    return Status::ok();
}

void Viewer::present() {
    glDrawBuffer(mStereoWindow ? GL_BACK_LEFT : GL_BACK);
    glClear(GL_COLOR_BUFFER_BIT);
    if (mStereoWindow) {
        glDrawBuffer(GL_BACK_RIGHT);
        glClear(GL_COLOR_BUFFER_BIT);
    }
    if (quadBuffer()) {
        mPresenter->draw(0, mFb, GL_BACK_LEFT);
        mPresenter->draw(1, mFb, GL_BACK_RIGHT);
    } else if (mGpuAnaglyph) {
        if (Status s = mPresenter->drawAnaglyph(*mGpuAnaglyph, mFb, GL_BACK); !s) {
            // Never expected (the GLSL is generated and tested), but then the CPU composes.
            mGpuAnaglyphFailed = true;
            say(s.message() + "; composing anaglyphs on the CPU");
            mNeedRender = true;
        }
    } else {
        mPresenter->draw(0, mFb, GL_BACK);  // both back buffers of a stereo window
    }
}

Status Viewer::writeScreenshot(const std::filesystem::path& path) {
    Image image;
    if (quadBuffer()) {
        const std::vector<Image> eyes = {Presenter::readBack(mFb, GL_BACK_LEFT),
                                         Presenter::readBack(mFb, GL_BACK_RIGHT)};
        auto sbs = composite::compose("sbs", eyes);
        if (!sbs) return sbs.status();
        image = std::move(sbs).value();
    } else {
        image = Presenter::readBack(mFb, mStereoWindow ? GL_BACK_LEFT : GL_BACK);
    }
    if (Status s = writePng(path, image); !s) return s;
    say(fmt::format("wrote {} ({}x{}{})", path.string(), image.width, image.height,
                    quadBuffer() ? ", left | right back buffers" : ""));
    return Status::ok();
}

std::filesystem::path Viewer::nextScreenshotPath() {
    ++mScreenshotCount;
    if (mOptions.screenshot.empty()) return fmt::format("mvr-view-{}.png", mScreenshotCount);
    const std::filesystem::path base(mOptions.screenshot);
    std::filesystem::path p =
        base.parent_path() /
        fmt::format("{}-{}{}", base.stem().string(), mScreenshotCount, base.extension().string());
    return p;
}

int Viewer::run() {
    if (Status s = mWorker.call([this] { return mBackends.make(); }); !s) return cli::fail(s);
    auto supports = [this](const MethodRef& ref) {
        return mWorker.call(
            [this, ref] { return mBackends.backend(ref.backend).supports(ref.method); });
    };
    Result<std::size_t> initial = chooseInitialMethod(mBackends, mOptions, supports);
    if (!initial) {
        shutdown();
        return cli::fail(initial.status());
    }
    mMethodIndex = *initial;
    // What f cycles: the N-view outputs first for a row of views, after the stereo formats for
    // a pair; lenticular with a calibration (or when asked for).
    std::vector<std::string> nView;
    for (const std::string& f : viewerViewFormats()) {
        if (f != "lenticular" || mOptions.calibrationGiven || mOptions.format == f)
            nView.push_back(f);
    }
    const std::vector<std::string> stereo = viewerFormats();
    mFormats = viewCount() > 2 ? nView : stereo;
    mFormats.insert(mFormats.end(), viewCount() > 2 ? stereo.begin() : nView.begin(),
                    viewCount() > 2 ? stereo.end() : nView.end());
    const auto& formats = mFormats;
    std::string first = mOptions.format;
    if (!mOptions.formatGiven && mPrepared.display) {
        // The preset's output: its quilt, or the lenticular image with a calibration.
        const std::string preset(mPrepared.display->format);
        first = preset == "quilt" && mOptions.calibrationGiven ? "lenticular" : preset;
        if (std::find(formats.begin(), formats.end(), first) == formats.end()) {
            fmt::print(stderr, "mvr view: --display {}: {} is not shown in a window; showing {}\n",
                       mPrepared.display->name, first, mOptions.format);
            first = mOptions.format;
        }
    }
    mFormatIndex = std::size_t(std::find(formats.begin(), formats.end(), first) - formats.begin());
    if (mFormatIndex >= formats.size()) mFormatIndex = 0;
    mFormatBeforeView = mFormatIndex;

    const glm::ivec2 viewSize(mSettings.width, mSettings.height);
    const glm::ivec2 windowSize = frameSizeFor(quadBuffer() ? "" : formatName(), viewSize);
    if (Status s = openWindow(windowSize); !s) {
        shutdown();
        return cli::fail(s);
    }
    if (quadBuffer() && !mStereoWindow) {
        fmt::print(stderr,
                   "mvr view: quad-buffer: the driver gives no stereo visual (GLFW_STEREO); "
                   "showing {} instead\n",
                   kQuadBufferFallback);
        mFormatIndex = std::size_t(std::find(formats.begin(), formats.end(), kQuadBufferFallback) -
                                   formats.begin());
    }
    if (mOptions.frames > 0 && std::size_t(mOptions.frames) < mScript.size()) {
        fmt::print(stderr, "mvr view: --frames {} ends before the script's {} steps\n",
                   mOptions.frames, mScript.size());
    }
    if (!mOptions.quiet) {
        glm::ivec2 opened = windowSize;  // scaled down when larger than the desktop
        glfwGetWindowSize(mWindow, &opened.x, &opened.y);
        fmt::print("mvr view: {} ({} triangles), {}, {}, window {}x{}{}\n", mPrepared.sceneName,
                   mPrepared.scene.triangleCount(), method().label(), formatName(), opened.x,
                   opened.y, mStereoWindow ? ", stereo visual (quad-buffer available)" : "");
        std::fflush(stdout);
    }

    int exit = 0;
    const bool scripted = mOptions.frames > 0;
    while (!mQuit && !glfwWindowShouldClose(mWindow)) {
        const bool stepping = mScriptNext < mScript.size();
        if (scripted || stepping) {
            glfwPollEvents();
        } else {
            // Interactive and idle: wait for input (the HUD still refreshes twice a second).
            glfwWaitEventsTimeout(mNeedRender ? 0.0 : 0.5);
        }
        if (stepping) applyStep(mScript[mScriptNext++]);
        if (mQuit) break;

        glfwGetFramebufferSize(mWindow, &mFb.x, &mFb.y);
        if (mFb.x < 2 || mFb.y < 2) continue;  // minimised
        const glm::ivec2 view = viewSizeFor(quadBuffer() ? "" : formatName(), mFb);
        if (view != glm::ivec2(mSettings.width, mSettings.height)) {
            mSettings.width = view.x;
            mSettings.height = view.y;
            mStereo.setAspect(float(view.x) / float(view.y));
            mNeedRender = true;
        }
        if (mPrepared.eyeTrack && mStereo.screenRig) {  // replayed; scripted: frame i at i/24 s
            const double t = scripted ? mFrames / 24.0 : msSince(mStarted) / 1000.0;
            mStereo.setEyes(mPrepared.eyeTrack->at(t, mStereo.screenRig->screen->screen));
            mNeedRender = true;
        }
        const auto start = Clock::now();
        const bool rendered = mNeedRender || scripted || !mRig;
        if (rendered) {
            if (Status s = renderFrame(); !s) {
                if (!mRig) {  // nothing to show at all
                    exit = cli::fail(s);
                    break;
                }
                say(fmt::format("{}: {}", method().label(), s.message()));
                mNeedRender = false;
            }
        }
        if (Status s = composeAndPresent(); !s) {
            exit = cli::fail(s);
            break;
        }
        if (rendered) {
            mFrameMs = msSince(start);
            mShownTiming = {mFrameMs, mRenderMs, mComposeMs};
        }
        if (mScreenshotRequested) {
            mScreenshotRequested = false;
            if (Status s = writeScreenshot(nextScreenshotPath()); !s) say(s.message());
        }
        glfwSwapBuffers(mWindow);
        ++mFrames;
        if (scripted && mFrames >= mOptions.frames) break;
    }
    if (exit == 0 && !mOptions.screenshot.empty() && mRig) {
        // The last frame, drawn again into the back buffer and read back: what the window shows.
        present();
        if (Status s = writeScreenshot(mOptions.screenshot); !s) exit = cli::fail(s);
    }
    if (exit == 0 && !mOptions.quiet) {
        fmt::print(
            "mvr view: {} frame{}; last: {}, {}, {}x{} per view, separation {:.2f}%, "
            "convergence {:.4g}\n",
            mFrames, mFrames == 1 ? "" : "s", method().label(), formatName(), mSettings.width,
            mSettings.height, 100.0 * mStereo.separation(), mStereo.convergence);
    }
    shutdown();
    return exit;
}

}  // namespace

int runViewerWindow(const ViewerOptions& options, session::Prepared prepared,
                    std::vector<ScriptStep> script) {
    Viewer viewer(options, std::move(prepared), std::move(script));
    return viewer.run();
}

}  // namespace mvr::viewer
