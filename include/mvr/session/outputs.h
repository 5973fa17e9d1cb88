// mvr/session/outputs.h — the one writer of a rendered frame's files (library mvr::session),
// used by `mvr render` (a still, every frame of a sequence, MPI rank 0) and by the Python
// module: view-N.png (and depth-N.png), anaglyph.png for a stereo pair (Dubois' red-cyan,
// composite::kDefaultAnaglyph), then one file per format under compositeFileName().
#pragma once

#include <filesystem>
#include <functional>
#include <optional>
#include <span>
#include <string_view>
#include <string>
#include <utility>
#include <vector>

#include "mvr/backends.h"
#include "mvr/composite/compose.h"
#include "mvr/composite/rgbd.h"
#include "mvr/core/image.h"
#include "mvr/core/render.h"
#include "mvr/core/rig.h"
#include "mvr/core/status.h"
#include "mvr/io/png.h"
#include "mvr/session/prepare.h"

namespace mvr::session {

/// What writeOutputs() writes besides the views.
struct FrameOutputs {
    std::vector<std::string> formats;  ///< composite formats, in order
    bool depth = false;                ///< depth-N.png for the views that have depth
    /// The composite options; writeOutputs() sets their baseline and convergence from the rig.
    composite::ComposeOptions compose;
    bool cameras = false;  ///< cameras.json: every view's matrices and intrinsics (cameras.h)
    /// The PNGs' compression: Fast by default (zlib level 1: ~3.7x faster to write than
    /// libpng's default for ~10 % more bytes; the pixels are the same in every mode).
    PngCompression png = PngCompression::Fast;
    bool depthExr = false;   ///< depth-N.exr (distances) instead of depth-N.png
    bool views = true;       ///< view-N.png
    bool composites = true;  ///< anaglyph.png for a pair and the formats' files
    /// --view-range A:B: the frame's views are views A..B of the whole rig; their files are
    /// named by their number in it (view-A.png ...). None: all views, from 0.
    std::optional<std::pair<int, int>> viewRange;
    /// Whether the frame's depth images are read: written (depth) or composed (rgbd's).
    bool readsDepth() const;
    /// Whether a frame of `viewCount` views (`depthViews` with depth) writes any file.
    bool writesFiles(std::size_t viewCount, std::size_t depthViews) const {
        return (views && viewCount > 0) || (depth && depthViews > 0) ||
               (cameras && viewCount > 0) || (composites && (viewCount == 2 || !formats.empty()));
    }
};

/// The files a prepared recipe writes per frame: its formats, composite options, compression
/// and WriteSet.
FrameOutputs frameOutputs(const Prepared& prepared);

/// Runs `jobs` on up to `threads` threads (0: the machine's cores; the caller's thread is one
/// of them); the first failure in the jobs' order, or ok.
Status runParallel(const std::vector<std::function<Status()>>& jobs, int threads = 0);

/// Where writing a frame's files took its time, in seconds (`mvr bench outputs`).
struct WriteTimes {
    double compose = 0.0;  ///< composing the image composites (the composing thread)
    /// Encoding the files (PNG deflate in memory; EXR depth, JPS and MPO files with their
    /// writing), summed over the worker threads that ran them.
    double encode = 0.0;
    double write = 0.0;  ///< writing the encoded PNG bytes to files, summed over the threads
    double wall = 0.0;   ///< the whole call (composing included), on the caller's clock
};

/// What writeOutputs() wrote.
struct WrittenFrame {
    std::vector<std::string> paths;  ///< every file, in the order written
    WriteTimes times;
    /// The composed image of `keepFormat` (an image format among the formats), when asked.
    std::optional<Image> kept;
};

/// A text file written with a frame's set, wherever its path is (the comfort report's JSON):
/// staged beside its place and moved with the set. `option` names it in errors.
struct ExtraFile {
    std::filesystem::path path;
    std::string text;
    std::string option;  ///< e.g. "--report-json"
};

struct ComposedImages;

/// Writes the files of one frame into `dir` as one set (mvr/session/pending.h): under a
/// staging folder inside `dir` (made, with `dir` when missing, only when a file is written:
/// "cannot create output directory '...'", ErrorCode::Output), moved into place when every file
/// is written; on any failure, `dir` is left as it was. `keepFormat` is composed even when
/// composites are not written. Image composites are composed where `backend` composes (a GPU
/// backend on its GPU; null: the CPU). `extra` files are written and moved with the set.
/// `precomposed`: image composites made already (as writeFrameFiles() takes them; --direct's
/// lenticular image, with `out` holding no view).
/// Errors: the first file that fails.
Result<WrittenFrame> writeOutputs(const std::filesystem::path& dir, const RenderOutput& out,
                                  const Rig& rig, const FrameOutputs& outputs,
                                  const Backend* backend, const std::string& keepFormat = {},
                                  const std::vector<ExtraFile>& extra = {},
                                  ComposedImages* precomposed = nullptr);

/// A frame's image composites composed ahead of writeFrameFiles() (composeImages()).
struct ComposedImages {
    std::vector<std::pair<std::string, Image>> images;  ///< format name, image
    double seconds = 0.0;                               ///< the time composing them took
};

/// Whether `backend` composes image formats on its own device (gl: on the GPU, through a GL
/// context of the thread that renders): its composites are then composed on that thread
/// (composeImages()) before a frame's files are handed to another thread to write.
bool composesOnDevice(const Backend* backend);

/// The image composites writeFrameFiles() would compose for this frame (the anaglyph of a
/// pair, the image formats written, `keepFormat`), composed now where `backend` composes, so
/// that the files can be written on another thread. Errors: the composer's.
Result<ComposedImages> composeImages(const RenderOutput& out, const Rig& rig,
                                     const FrameOutputs& outputs, const Backend* backend,
                                     const std::string& keepFormat = {});

/// writeOutputs() without the staging: the files straight into `dir`, which exists (a
/// sequence's frame folder, itself written under a temporary name). `precomposed`: the
/// frame's image composites, composed already (composeImages(); taken from it), the others are
/// composed here.
Result<WrittenFrame> writeFrameFiles(const std::filesystem::path& dir, const RenderOutput& out,
                                     const Rig& rig, const FrameOutputs& outputs,
                                     const Backend* backend, const std::string& keepFormat = {},
                                     ComposedImages* precomposed = nullptr);

/// The rig's centre view: the middle one of a row (or grid) of an odd number of columns and
/// rows; -1 when there is none (an even count).
int centreView(const Rig& rig);

/// A colour-and-depth format's (rgbd, composite/rgbd.h) two images of a rendered frame: the
/// centre view's colour and its depth image, normalised between the nearest and farthest
/// distance drawn in it (the view's near and far planes when nothing was drawn), and what
/// its sidecar says (the image name left for the caller). `who` names the format in errors:
/// no centre view (ErrorCode::Usage), no depth images (the method gives none: Unsupported).
struct ColourAndDepth {
    std::vector<Image> images;  ///< {colour, depth image}
    composite::RgbdSidecar sidecar;
};
Result<ColourAndDepth> colourAndDepthOf(const RenderOutput& out, const Rig& rig,
                                        const std::string& who);
/// Before rendering: the rig has a centre view (else "WHO: the RGB-D image is the rig's centre
/// view, and N views have none (give an odd --views, e.g. --views 1)").
Status checkCentreView(const Rig& rig, const std::string& who);

/// Whether `mvr compose -o OUT` (mvr.compose(output=OUT)) names a file — OUT ends in .png, .jpg,
/// .jpeg, .jps or .mpo — rather than a folder.
bool isComposedFileName(const std::filesystem::path& out);

/// The file of `mvr compose -o OUT` and mvr.compose(output=OUT): OUT itself when it is a file
/// name (isComposedFileName(); its folder made), else DIR/<the format's file>
/// (composite::writeComposite()). Whole or not at all (mvr/session/pending.h): a failure leaves
/// OUT as it was. Returns the path written.
Result<std::filesystem::path> writeComposed(std::string_view format, std::span<const Image> views,
                                            const composite::ComposeOptions& options,
                                            const std::filesystem::path& out);

/// Writes `text` to the file `path` (the comfort report's JSON); false when it could not.
bool writeTextFile(const std::string& path, const std::string& text);

}  // namespace mvr::session
