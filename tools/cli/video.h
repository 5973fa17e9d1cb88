// tools/cli/video.h — video files of a sequence through FFmpeg's libraries (libavformat,
// libavcodec, libswscale; H.264 through libx264), when the build found them (MVR_WITH_VIDEO).
// The file is written under "<stem>.part<ext>" and renamed when finished; a failed or
// interrupted run leaves no file under the final name.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "mvr/core/image.h"
#include "mvr/core/status.h"

namespace mvr::cli {

/// Matroska StereoMode name of a composite format ("left_right" for sbs, ...); empty if none.
std::string matroskaStereoMode(const std::string& format, bool swapped);

/// A video's encoder (--codec, --crf, --encoder-preset). Defaults, per codec (preset / CRF):
/// h264 libx264 fast / 18, h265 libx265 fast / 20, av1 SVT-AV1 10 / 30 (frames of at least
/// 64x64), ffv1 lossless RGBA (.mkv only; any size; no CRF or preset).
struct VideoCodec {
    std::string codec = "h264";
    int crf = -1;        ///< -1: the codec's default
    std::string preset;  ///< empty: the codec's default
};

/// Refuses, before anything is rendered, what the codec cannot take: an unknown codec, a CRF
/// out of its range, ffv1 in MP4 or with a CRF/preset, an odd or too small size for the
/// 4:2:0 codecs. Errors: ErrorCode::Usage naming the option.
Status checkVideo(const std::string& path, const VideoCodec& codec, int width, int height);

class VideoWriter {
public:
    /// Opens `path` (.mkv or .mp4) for `streams` streams of width×height at `fps`.
    /// `stereoMode`: Matroska StereoMode name for stream 0 ("" none). Errors: Usage (extension,
    /// size, codec: checkVideo()), Unsupported (no FFmpeg in this build, no such encoder, a
    /// preset the encoder refuses), Output.
    static Result<std::unique_ptr<VideoWriter>> open(const std::string& path, int streams,
                                                     int width, int height, double fps,
                                                     const std::string& stereoMode,
                                                     const VideoCodec& codec = {});
    virtual ~VideoWriter() = default;
    /// Encodes one frame of stream `stream`.
    virtual Status add(int stream, const Image& image) = 0;
    /// Flushes, writes the trailer and renames the file into place.
    virtual Status finish() = 0;
};

bool videoAvailable();


}  // namespace mvr::cli
