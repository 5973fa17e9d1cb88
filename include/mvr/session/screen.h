// mvr/session/screen.h — `--rig screen`'s options (RenderRecipe::screen) as the screen and eyes
// of mvr/core/screen_rig.h, and the rig placed around a framed scene.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "mvr/core/displays.h"
#include "mvr/core/screen_rig.h"
#include "mvr/session/recipe.h"

namespace mvr::session {

struct EyeTrack;

/// The screen and eyes `r.screen` gives (defaults in ScreenRecipe), for views of `viewAspect`
/// (width / height). Errors: Usage naming the option and its value (a malformed or
/// out-of-range number, both --eyes and --head / --ipd-mm, corners that are no rectangle, an
/// eye behind the screen).
/// With an eye track (`r.screen.eyeTrack`), the eyes are its first sample's and `track` gets
/// the track read (readEyeTrack()).
/// `display`: a tracked monitor's preset gives the screen's size when no option does.
Result<ScreenEyes> screenEyesOf(const RenderRecipe& r, float viewAspect,
                                std::shared_ptr<const EyeTrack>* track = nullptr,
                                const DisplayPreset* display = nullptr);

/// The comfort report's screen (cm): the screen's width, the eyes' midpoint's distance to its
/// plane and their distance apart.
ScreenGeometry screenGeometryOf(const ScreenEyes& eyes);

/// Whether `r` renders with the screen rig: --rig screen, or a tracked monitor's preset
/// (DisplayPreset::tracked()) with the default rig.
bool usesScreenRig(const RenderRecipe& r, const DisplayPreset* display);

/// A per-frame eye track (`--eye-track FILE`, docs/displays.md): what an eye tracker logged,
/// one CSV row per sample, `t,lx,ly,lz,rx,ry,rz` (seconds; the left and right eye in mm of
/// screen space, as --eyes). A first line that is not numbers is a header; blank lines and
/// lines starting with '#' are skipped; times strictly increase. Frame f of a sequence takes
/// the eyes at time f / --fps, interpolated linearly between the rows around it and held
/// before the first row and after the last.
/// The SR runtimes' factors applied to a pair of eyes: their distance scaled by `depth` about
/// their midpoint, the midpoint's offset from `home` (the default head) scaled by `lookAround`.
struct EyeFactors {
    float depth = 1.0f;
    float lookAround = 1.0f;
    glm::vec3 home{0.0f, 0.0f, 600.0f};
    ScreenEyes apply(ScreenEyes eyes) const;
};

struct EyeTrack {
    struct Sample {
        double t = 0.0;
        glm::vec3 left{0.0f}, right{0.0f};
    };
    std::vector<Sample> samples;  ///< at least one, times ascending
    EyeFactors factors;           ///< applied by at()
    double duration() const { return samples.empty() ? 0.0 : samples.back().t; }
    /// The eyes at `t` seconds on `screen`, the factors applied.
    ScreenEyes at(double t, const ScreenCorners& screen) const;
};
/// Reads and checks an eye track: every row's eyes in front of `screen` (validateScreenEyes).
/// Errors: Input naming the file and its line ("--eye-track eyes.csv: line 4: expected 7
/// numbers t,lx,ly,lz,rx,ry,rz, got 6"), a missing or empty file.
Result<EyeTrack> readEyeTrack(const std::string& file, const ScreenCorners& screen);

/// The warning that views of `width` x `height` pixels stretch onto `screen` (their aspect is
/// not the screen's, by more than 1 %), with the --size that keeps the pixels square; none
/// when the aspects agree.
std::optional<std::string> screenStretchNote(const ScreenCorners& screen, int width, int height);

/// Refuses what `--rig screen` cannot take: other than two views, --view-grid, --view-cone,
/// --interaxial / --separation (auto or not; the eyes give the spacing), an eye track without a
/// sequence or beside --eyes / --head, and screen options without `--rig screen`. Usage errors naming the option.
Status checkScreenOptions(const RenderRecipe& r, int views, bool screenRig);

}  // namespace mvr::session
