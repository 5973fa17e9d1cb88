// mvr/session/recipe.h — every input of `mvr render` as one plain struct (library mvr::session).
//
// A RenderRecipe says what to render: the models (or a named scene), the views and their rig,
// the image, the surfaces drawn after the scene, the sequence and the outputs. prepare()
// (mvr/session/prepare.h) turns it into the scene, rig and settings that `mvr render` renders,
// with the same checks and the same messages (they name the command-line options: "--fov nan is
// out of range ..."); writeOutputs() (mvr/session/outputs.h) writes a frame's files. The `mvr`
// tool fills a recipe from its options, the Python module from its keywords, the viewer from
// its own options: all three get the same scene for the same inputs.
//
// Optional fields are "not given": prepare() then uses the default (or a display preset's value,
// which a given field overrides).
#pragma once

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mvr/composite/compose.h"
#include "mvr/core/image.h"
#include "mvr/core/mesh.h"
#include "mvr/io/png.h"

namespace mvr::session {

/// What is drawn into every view after the scene (mvr/core/stereo_surfaces.h): --sky,
/// --floating-window, --letterbox, --label, --label-anchor.
struct SurfaceRecipe {
    std::string sky;  ///< "gradient" or a PNG / JPEG map; empty: none
    bool floatingWindow = false;
    double letterbox = 0.0;           ///< percent of the height per band; 0: none
    std::vector<std::string> labels;  ///< "TEXT@x,y[,distance]"
    std::vector<std::string> anchors;  ///< "TEXT@X,Y,Z"
    /// --angular-aa: "auto" | "off" | a scale S (mvr/core/angular_aa.h; resolveAngularAA()).
    std::string angularAA = "auto";
};

/// A sequence (--frames, --orbit, --camera-path ...): active() when any of the three is given.
struct SequenceRecipe {
    int frames = 0;          ///< 0: none (or the camera path's length)
    double orbit = 0.0;      ///< degrees about the scene centre over the frames
    std::string cameraPath;  ///< keyframes, JSON (docs/animation.md)
    std::string frameRange;  ///< "A:B" (inclusive A, exclusive B); empty: all
    std::string shard;       ///< "I/N": frames f with f mod N == I; empty: all
    double fps = 24.0;       ///< camera path times, the video's rate
    std::string video;       ///< .mkv | .mp4 (the `mvr` tool's FFmpeg); empty: none
    std::string codec = "h264";  ///< the video's: h264 | h265 | av1 | ffv1 (lossless, .mkv)
    int crf = -1;                ///< the video's quality (lower: better); -1: the codec's default
    std::string encoderPreset;   ///< the encoder's speed preset; empty: the codec's default
    int threads = 0;         ///< CPU threads of the backend per process; 0: the default
    bool gatherStats = false;  ///< MPI: rank 0's gather time per frame
    bool active() const { return frames > 0 || orbit != 0.0 || !cameraPath.empty(); }
};

/// The files of a render (writeOutputs()): DIR/view-N.png, depth-N.png, anaglyph.png for a
/// pair, one file per format; for a sequence, the same per DIR/frame-NNNN/.
struct OutputRecipe {
    std::string directory;             ///< empty: nothing written (the library returns images)
    std::vector<std::string> formats;  ///< composite formats (composite::formatNames())
    bool depth = false;                ///< also depth-N.png (16-bit, near = black)
    bool cameras = false;              ///< also cameras.json (mvr/session/cameras.h)
    std::string pngCompression = "fast";  ///< fast | default | small (PngCompression)
    /// The depth files: png16 (depth-N.png, 16-bit, near = black) or exr (depth-N.exr, linear
    /// eye-space distance in world units: mvr/io/exr.h).
    std::string depthFormat = "png16";
    /// What is written (--write): a comma list of views, depth, composites, cameras, video;
    /// empty: the defaults (prepare()'s WriteSet). depth and cameras also follow `depth` and
    /// `cameras`.
    std::string write;
    std::string reportJson;            ///< the comfort report as JSON; empty: none
    /// The composite options. Their baseline and convergence are the rig's at writing time.
    composite::ComposeOptions compose;
    bool calibrationGiven = false;  ///< compose.lenticular comes from a visual.json
    bool quiltGiven = false;        ///< compose.quilt* were given (a preset keeps them)
    /// --direct: the lenticular image composed from the views' rows as soft:unified finishes
    /// them, with no view or quilt in memory (mvr/session/direct.h); a display preset then
    /// writes its lenticular image alone.
    bool direct = false;
};

/// The centre camera's viewpoint when the caller gives one (over the file's camera and the
/// framed default). One family at a time: orbit-style (azimuth / elevation / distance /
/// target, about the framed scene: f3d's and Blender's habit), eye and look-at, or a matrix.
/// Any of them: the file's camera (and its animation) is not used.
struct CameraRecipe {
    std::optional<double> azimuth;    ///< degrees about +Y; 0: from +Z, 90: from +X
    std::optional<double> elevation;  ///< degrees above the horizontal plane, [-90, 90]
    std::optional<double> distance;   ///< world units from the target; nullopt: fit the scene
    std::string target;               ///< "X,Y,Z", or "centre" (default: the bounds' centre)
    std::string position;             ///< "X,Y,Z": the eye
    std::string lookAt;               ///< "X,Y,Z" (default: the bounds' centre)
    std::string up;                   ///< "X,Y,Z" (default 0,1,0)
    /// A 4x4 world-from-camera matrix, row-major (the camera looks down its -Z, +Y up): 16
    /// numbers, or a file holding them (whitespace, commas or a JSON array).
    std::string matrix;
    std::optional<double> focalLengthMm;  ///< with sensorWidthMm: the horizontal field of view
    double sensorWidthMm = 36.0;
    bool given() const {
        return azimuth || elevation || distance || !target.empty() || !position.empty() ||
               !lookAt.empty() || !up.empty() || !matrix.empty();
    }
};

/// `--rig screen` (mvr/core/screen_rig.h): the physical screen and the viewer's eyes, in mm of
/// screen space (the screen centred on the origin, facing +Z, unless corners are given).
struct ScreenRecipe {
    /// --screen-mm "WxH"; default: --screen-width (cm) at the views' aspect, else a 27-inch
    /// 16:9 panel (597.9 x 336.3 mm, the size of the eye-tracked monitors' presets).
    std::string size;
    std::string corners;  ///< --screen-corners "LL;LR;UL", each X,Y,Z; excludes size
    std::string eyes;     ///< --eyes "LX,LY,LZ;RX,RY,RZ"; excludes ipdMm and head
    std::optional<double> ipdMm;  ///< --ipd-mm (default 63: the adult mean)
    /// --head X,Y,Z: the eyes' midpoint; default (0, 0, --viewing-distance in mm, else 600).
    std::string head;
    /// --eye-track FILE: the eyes per frame of a sequence (screen.h's EyeTrack); excludes eyes
    /// and head.
    std::string eyeTrack;
    /// The SR runtimes' factors (docs/displays.md): --depth-factor scales the eyes' distance
    /// about their midpoint ("Depth Factor"), --look-around the head's movement away from the
    /// default head ("Look Around Factor"); 1: as given.
    std::optional<double> depthFactor, lookAround;
    /// --screen-tilt DEG: the screen leaning back about its horizontal centre line (the top
    /// away from the viewer); default the display preset's (45 for Sony's), else 0. Excludes
    /// corners.
    std::optional<double> tiltDegrees;
    bool given() const {
        return !size.empty() || !corners.empty() || !eyes.empty() || ipdMm || !head.empty() ||
               !eyeTrack.empty() || depthFactor || lookAround || tiltDegrees;
    }
};

/// A mesh given in memory (Python's mvr.Mesh), rendered with the model files (after them).
struct InlineModel {
    std::string name;                  ///< for the scene's name and messages
    std::shared_ptr<const Mesh> mesh;  ///< validated, with normals
    std::optional<Image> texture;      ///< base colour texture (the mesh has texcoords)
    std::string placement;             ///< "X,Y,Z[,SCALE[,YAW]]" as a model's FILE@...; empty: none
};

struct RenderRecipe {
    // ---- the scene ----
    /// Model files (OBJ, PLY, glTF), each optionally placed: FILE@X,Y,Z[,SCALE[,YAW]].
    std::vector<std::string> models;
    std::vector<InlineModel> meshes;  ///< in-memory meshes, after the files
    std::string scene = "default";  ///< without models: default | village | textured
    int grid = 1;                   ///< copies of the model(s) in a grid
    bool noFileCamera = false;      ///< frame the bounds instead of the file's camera
    bool strict = false;            ///< a model's missing texture is an error (else a warning)
    std::optional<double> exposure;  ///< EV (stops)
    bool exposureAuto = false;
    /// none | khr-neutral | aces | auto (khr-neutral when the models' own lights light the
    /// scene: KHR_lights_punctual is in physical units; else none). Scene::tonemap.
    std::string tonemap = "auto";
    /// An environment map lighting the scene (issue 39 item 2; loadEnvironmentMap: .hdr, .exr,
    /// PNG or JPEG, equirectangular or cube cross); empty: none.
    std::string environment;
    int billboards = 0;           ///< camera-facing quads scattered through the bounds
    double billboardSize = 0.0;   ///< 0: 3 % of the scene's radius

    // ---- the views and the rig ----
    std::optional<int> views;  ///< a row of N views (default 2, or the display's)
    std::string viewGrid;      ///< "CxR"; excludes views
    std::string display;       ///< a display preset (mvr/core/displays.h); empty: none
    std::string rig = "offaxis";  ///< offaxis | toein | parallel | screen
    ScreenRecipe screen;          ///< rig "screen": the screen and the eyes
    std::optional<double> interaxial;
    std::optional<double> separation;
    bool separationAuto = false;  ///< needs screenWidthCm
    /// With separationAuto: the largest parallax as a percentage of the screen's budget,
    /// 0 < P <= 100 (default 100, displays.h kDefaultDepthPercent).
    std::optional<double> depthPercent;
    std::optional<double> convergence;
    bool convergenceAuto = false;
    std::optional<double> viewCone;  ///< degrees; an off-axis row
    /// "A:B": render only views A..B (both included) of the rig (mvr/session/view_range.h);
    /// empty: all of them.
    std::string viewRange;
    /// A calibration's view cone (visual.json "viewCone"): the default cone where a preset's
    /// would apply; viewCone wins.
    std::optional<double> calibrationViewCone;
    std::optional<double> fov;  ///< degrees (default: the file camera's, else 45)
    std::optional<double> screenWidthCm;
    std::optional<double> viewingDistanceCm;
    CameraRecipe camera;  ///< the centre camera's viewpoint, when given

    // ---- the image ----
    std::optional<std::string> size;  ///< "WxH" per view (default 1024x768, or the display's)
    std::string shading = "vertex";  ///< flat | vertex | pixel
    /// --specular center | per-view (RenderSettings::specular): per-view shades each view from
    /// its own eye, per pixel (vertex shading becomes pixel; flat is refused).
    std::string specular = "center";
    bool cull = false;
    bool wireframe = false;
    bool shadows = false;
    int shadowMapSize = 1024;
    /// --aa N: samples a pixel, 1, 2, 4, 8 (sampling.h; default 4 for light-field displays, 1).
    std::optional<int> aa;
    /// --synthesize K: every K-th view of a row (and its last) rendered exactly, the others
    /// warped from their depth (mvr/core/synthesize.h); 1: every view exact.
    int synthesize = 1;
    std::string background;  ///< "R,G,B" in [0, 1] or "#RRGGBB"; empty: the scene's

    // ---- what is drawn after the scene, the sequence, the outputs and the backend ----
    SurfaceRecipe surfaces;
    SequenceRecipe sequence;
    OutputRecipe outputs;
    std::string backend;  ///< empty: the registry's first backend
    std::string method;   ///< empty: the backend's default method
    /// The options given explicitly, by their `mvr render` names ("--fps"): prepare() warns of
    /// those this recipe ignores (ignoredOptionWarnings()). Optional: empty, no such warning.
    std::vector<std::string> given;
    /// Whether `option` ("--fps") is among `given`.
    bool gave(std::string_view option) const {
        return std::find(given.begin(), given.end(), option) != given.end();
    }
};

}  // namespace mvr::session
