#include "video.h"

#include "mvr/session/pending.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <map>

#include <fmt/core.h>

#ifdef MVR_WITH_VIDEO
extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/opt.h>
#include <libavutil/stereo3d.h>
#include <libswscale/swscale.h>
}
#endif

namespace mvr::cli {

std::string matroskaStereoMode(const std::string& format, bool swapped) {
    // The names FFmpeg's matroska muxer maps to StereoMode (libavformat/matroska.c).
    static const std::map<std::string, std::pair<std::string, std::string>> kModes = {
        {"sbs", {"left_right", "right_left"}},
        {"sbs-half", {"left_right", "right_left"}},
        {"tb", {"top_bottom", "bottom_top"}},
        {"tb-half", {"top_bottom", "bottom_top"}},
        {"rows", {"row_interleaved_lr", "row_interleaved_rl"}},
        {"columns", {"col_interleaved_lr", "col_interleaved_rl"}},
        {"checkerboard", {"checkerboard_lr", "checkerboard_rl"}},
        {"anaglyph-color", {"anaglyph_cyan_red", "anaglyph_cyan_red"}},
        {"anaglyph-half-color", {"anaglyph_cyan_red", "anaglyph_cyan_red"}},
        {"anaglyph-gray", {"anaglyph_cyan_red", "anaglyph_cyan_red"}},
        {"anaglyph-dubois", {"anaglyph_cyan_red", "anaglyph_cyan_red"}},
        {"anaglyph-dubois-gm", {"anaglyph_green_magenta", "anaglyph_green_magenta"}},
    };
    auto it = kModes.find(format);
    if (it == kModes.end()) return {};
    return swapped ? it->second.second : it->second.first;
}

namespace {

/// The codecs of --codec: FFmpeg's encoder, the default preset and CRF (docs/animation.md), the
/// CRF's range (0: none), the smallest side, and whether frames are 4:2:0 (even sizes) or
/// lossless BGRA.
struct CodecRow {
    const char* name;
    const char* label;
    const char* encoder;
    const char* preset;
    int crf;
    int maxCrf;
    int minSide;
    bool yuv420;
};
constexpr CodecRow kCodecs[] = {
    {"h264", "H.264", "libx264", "fast", 18, 51, 2, true},
    {"h265", "H.265", "libx265", "fast", 20, 51, 2, true},
    {"av1", "AV1", "libsvtav1", "10", 30, 63, 64, true},
    {"ffv1", "FFV1", "ffv1", "", -1, 0, 1, false},
};

const CodecRow* findCodec(const std::string& name) {
    for (const CodecRow& row : kCodecs)
        if (name == row.name) return &row;
    return nullptr;
}

}  // namespace

Status checkVideo(const std::string& path, const VideoCodec& c, int width, int height) {
    const std::string ext = std::filesystem::path(path).extension().string();
    if (ext != ".mkv" && ext != ".mp4") {
        return usageError(fmt::format("--video {}: expected a .mkv or .mp4 file", path));
    }
    const CodecRow* row = findCodec(c.codec);
    if (!row) {
        return usageError(
            fmt::format("--codec {}: unknown codec (expected h264, h265, av1 or ffv1)", c.codec));
    }
    if (row->maxCrf == 0 && c.crf != -1) {
        return usageError(fmt::format("--crf {}: {} is lossless (no CRF)", c.crf, row->name));
    }
    if (row->maxCrf > 0 && (c.crf < -1 || c.crf > row->maxCrf)) {
        return usageError(fmt::format("--crf {} is out of range for {} (expected 0..{})", c.crf,
                                      row->name, row->maxCrf));
    }
    if (!*row->preset && !c.preset.empty()) {
        return usageError(
            fmt::format("--encoder-preset {}: {} has no presets", c.preset, row->name));
    }
    if (!row->yuv420 && ext != ".mkv") {
        return usageError(
            fmt::format("--codec {}: lossless FFV1 goes in a .mkv file (--video {})", c.codec, path));
    }
    if (row->yuv420 && (width % 2 || height % 2)) {
        return usageError(fmt::format(
            "--video {}: {} 4:2:0 needs an even width and height (the frames are {}x{})", path,
            row->label, width, height));
    }
    if (width < row->minSide || height < row->minSide) {
        return usageError(fmt::format(
            "--codec {}: {} needs frames of at least {}x{} (they are {}x{})", c.codec,
            row->encoder, row->minSide, row->minSide, width, height));
    }
    return {};
}

#ifndef MVR_WITH_VIDEO

bool videoAvailable() { return false; }

Result<std::unique_ptr<VideoWriter>> VideoWriter::open(const std::string& path, int, int, int,
                                                       double, const std::string&,
                                                       const VideoCodec&) {
    return unsupportedError(fmt::format(
        "--video {}: this mvr was built without FFmpeg (libavcodec, libavformat, libswscale)",
        path));
}

#else

bool videoAvailable() { return true; }

namespace {

std::string averr(int code) {
    char buf[AV_ERROR_MAX_STRING_SIZE] = {};
    av_strerror(code, buf, sizeof buf);
    return buf;
}

struct Stream {
    AVStream* st = nullptr;
    AVCodecContext* ctx = nullptr;
    AVFrame* frame = nullptr;
    SwsContext* sws = nullptr;
    long pts = 0;
};

class FfmpegWriter final : public VideoWriter {
public:
    ~FfmpegWriter() override {
        for (Stream& s : mStreams) {
            sws_freeContext(s.sws);
            av_frame_free(&s.frame);
            avcodec_free_context(&s.ctx);
        }
        if (mFc) {
            if (mFc->pb) avio_closep(&mFc->pb);
            avformat_free_context(mFc);
        }
        if (mTicket >= 0) session::releasePending(mTicket, !mFinished);
        av_packet_free(&mPacket);
    }

    Status init(const std::string& path, int streams, int width, int height, double fps,
                const std::string& stereoMode, const VideoCodec& choice) {
        mPath = path;
        const std::filesystem::path p(path);
        mTemp = (p.parent_path() / (p.stem().string() + ".part" + p.extension().string())).string();
        int rc = avformat_alloc_output_context2(&mFc, nullptr, nullptr, mTemp.c_str());
        if (rc < 0 || !mFc) return outputError(fmt::format("--video {}: {}", path, averr(rc)));
        mFc->flags |= AVFMT_FLAG_BITEXACT;  // no dates or library versions: reproducible files
        mFc->strict_std_compliance = FF_COMPLIANCE_UNOFFICIAL;  // MP4: st3d is "unofficial"
        const CodecRow& row = *findCodec(choice.codec);  // checkVideo() found it
        const AVCodec* codec = avcodec_find_encoder_by_name(row.encoder);
        if (!codec && std::string(row.name) == "h264") codec = avcodec_find_encoder(AV_CODEC_ID_H264);
        if (!codec) {
            return unsupportedError(fmt::format("--codec {}: this FFmpeg has no {} encoder",
                                                choice.codec, row.encoder));
        }
        const AVPixelFormat pixels = row.yuv420 ? AV_PIX_FMT_YUV420P : AV_PIX_FMT_BGRA;
        const std::string preset = choice.preset.empty() ? row.preset : choice.preset;
        const int crf = choice.crf >= 0 ? choice.crf : row.crf;
        const AVRational rate = av_d2q(fps, 1000);
        mPacket = av_packet_alloc();
        for (int i = 0; i < streams; ++i) {
            Stream s;
            s.st = avformat_new_stream(mFc, nullptr);
            s.ctx = avcodec_alloc_context3(codec);
            if (!s.st || !s.ctx) return internalError("--video: out of memory");
            s.ctx->width = width;
            s.ctx->height = height;
            s.ctx->pix_fmt = pixels;
            s.ctx->time_base = av_inv_q(rate);
            s.ctx->framerate = rate;
            s.ctx->gop_size = 24;
            s.ctx->thread_count = 1;  // same bytes on every run
            s.ctx->flags |= AV_CODEC_FLAG_BITEXACT;
            if (mFc->oformat->flags & AVFMT_GLOBALHEADER) {
                s.ctx->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
            }
            if (!preset.empty() &&
                av_opt_set(s.ctx->priv_data, "preset", preset.c_str(), 0) < 0) {
                return usageError(fmt::format("--encoder-preset {}: {} does not know it", preset,
                                              row.encoder));
            }
            if (crf >= 0) av_opt_set(s.ctx->priv_data, "crf", std::to_string(crf).c_str(), 0);
            if (std::string(row.name) == "h265") {  // quiet, and the same bytes on every run
                av_opt_set(s.ctx->priv_data, "x265-params",
                           "log-level=error:pools=none:frame-threads=1", 0);
            }
            if ((rc = avcodec_open2(s.ctx, codec, nullptr)) < 0 && !choice.preset.empty()) {
                return usageError(fmt::format("--encoder-preset {}: {} refused it ({})", preset,
                                              row.encoder, averr(rc)));
            }
            if (rc < 0) {
                return unsupportedError(fmt::format("--video {}: cannot open {} (preset {}): {}",
                                                    path, codec->name, preset, averr(rc)));
            }
            avcodec_parameters_from_context(s.st->codecpar, s.ctx);
            s.st->time_base = s.ctx->time_base;
            s.st->avg_frame_rate = rate;
            if (i == 0 && !stereoMode.empty()) {
                // Matroska: the muxer turns this tag into the StereoMode element.
                av_dict_set(&s.st->metadata, "stereo_mode", stereoMode.c_str(), 0);
                // MP4: the stereo3d side data becomes an st3d box (side by side, top bottom).
                int type = -1;
                if (stereoMode == "left_right" || stereoMode == "right_left") {
                    type = AV_STEREO3D_SIDEBYSIDE;
                } else if (stereoMode == "top_bottom" || stereoMode == "bottom_top") {
                    type = AV_STEREO3D_TOPBOTTOM;
                }
                if (type >= 0 && std::string(mFc->oformat->name).find("mp4") != std::string::npos) {
                    auto* s3d = reinterpret_cast<AVStereo3D*>(
                        av_stream_new_side_data(s.st, AV_PKT_DATA_STEREO3D, sizeof(AVStereo3D)));
                    if (s3d) {
                        *s3d = AVStereo3D{};
                        s3d->type = AVStereo3DType(type);
                        if (stereoMode == "right_left" || stereoMode == "bottom_top") {
                            s3d->flags = AV_STEREO3D_FLAG_INVERT;
                        }
                    }
                }
            }
            s.frame = av_frame_alloc();
            s.frame->format = pixels;
            s.frame->width = width;
            s.frame->height = height;
            if (av_frame_get_buffer(s.frame, 0) < 0) return internalError("--video: out of memory");
            s.sws = sws_getContext(
                width, height, AV_PIX_FMT_RGBA, width, height, pixels,
                (row.yuv420 ? SWS_BICUBIC : SWS_POINT) | SWS_BITEXACT | SWS_ACCURATE_RND, nullptr,
                nullptr, nullptr);
            if (!s.sws) return internalError("--video: no conversion from RGBA");
            mStreams.push_back(s);
        }
        // Its folder made when missing (kept with the video, else removed when empty).
        auto folder = session::MadeFolders::make(std::filesystem::path(mTemp).parent_path().empty()
                                                     ? std::filesystem::path(".")
                                                     : std::filesystem::path(mTemp).parent_path());
        if (!folder) {
            return Status(folder.status().code(),
                          fmt::format("--video {}: {}", path, folder.status().message()));
        }
        mFolder = std::move(folder).value();
        std::unique_lock made(session::pendingMutex());  // registered and made at once
        mTicket = session::addPending(mTemp);  // removed should the run stop
        rc = avio_open(&mFc->pb, mTemp.c_str(), AVIO_FLAG_WRITE);
        made.unlock();
        if (rc < 0) {
            return outputError(
                fmt::format("--video {}: cannot write '{}': {}", path, mTemp, averr(rc)));
        }
        if ((rc = avformat_write_header(mFc, nullptr)) < 0) {
            return outputError(fmt::format("--video {}: {}", path, averr(rc)));
        }
        return {};
    }

    Status drain(Stream& s) {
        for (;;) {
            int rc = avcodec_receive_packet(s.ctx, mPacket);
            if (rc == AVERROR(EAGAIN) || rc == AVERROR_EOF) return {};
            if (rc < 0) return internalError(fmt::format("--video {}: {}", mPath, averr(rc)));
            av_packet_rescale_ts(mPacket, s.ctx->time_base, s.st->time_base);
            mPacket->stream_index = s.st->index;
            rc = av_interleaved_write_frame(mFc, mPacket);
            if (rc < 0) return outputError(fmt::format("--video {}: {}", mPath, averr(rc)));
        }
    }

    Status add(int stream, const Image& image) override {
        Stream& s = mStreams.at(std::size_t(stream));
        if (image.width != s.ctx->width || image.height != s.ctx->height) {
            return internalError(fmt::format("--video {}: frame of {}x{} for a {}x{} stream", mPath,
                                             image.width, image.height, s.ctx->width,
                                             s.ctx->height));
        }
        if (av_frame_make_writable(s.frame) < 0) return internalError("--video: out of memory");
        const uint8_t* src[1] = {reinterpret_cast<const uint8_t*>(image.rgba.data())};
        const int stride[1] = {image.width * 4};
        sws_scale(s.sws, src, stride, 0, image.height, s.frame->data, s.frame->linesize);
        s.frame->pts = s.pts++;
        if (int rc = avcodec_send_frame(s.ctx, s.frame); rc < 0) {
            return internalError(fmt::format("--video {}: {}", mPath, averr(rc)));
        }
        return drain(s);
    }

    Status finish() override {
        for (Stream& s : mStreams) {
            avcodec_send_frame(s.ctx, nullptr);
            if (Status st = drain(s); !st) return st;
        }
        if (int rc = av_write_trailer(mFc); rc < 0) {
            return outputError(fmt::format("--video {}: {}", mPath, averr(rc)));
        }
        avio_closep(&mFc->pb);
        std::lock_guard lock(session::pendingMutex());  // not stopped half-way
        std::error_code ec;
        std::filesystem::rename(mTemp, mPath, ec);
        if (ec) {
            return outputError(
                fmt::format("--video {}: cannot rename '{}': {}", mPath, mTemp, ec.message()));
        }
        mFinished = true;
        mFolder.keep();
        return {};
    }

private:
    std::string mPath, mTemp;
    int mTicket = -1;  ///< mTemp's in session::addPending()
    session::MadeFolders mFolder;  ///< the video's folder, when this made it
    AVFormatContext* mFc = nullptr;
    AVPacket* mPacket = nullptr;
    std::vector<Stream> mStreams;
    bool mFinished = false;
};

}  // namespace

Result<std::unique_ptr<VideoWriter>> VideoWriter::open(const std::string& path, int streams,
                                                       int width, int height, double fps,
                                                       const std::string& stereoMode,
                                                       const VideoCodec& codec) {
    if (Status s = checkVideo(path, codec, width, height); !s) return s;
    av_log_set_level(AV_LOG_FATAL);  // the encoders' own lines: mvr says it in one
    ::setenv("SVT_LOG", "1", 0);  // SVT-AV1: errors only (its banner goes to stderr)
    auto w = std::make_unique<FfmpegWriter>();
    if (Status s = w->init(path, streams, width, height, fps, stereoMode, codec); !s) return s;
    return std::unique_ptr<VideoWriter>(std::move(w));
}

#endif

}  // namespace mvr::cli
