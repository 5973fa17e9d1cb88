// src/io/exr.cpp — depth as OpenEXR (mvr/io/exr.h) through OpenEXR's C++ scanline API.
#include "mvr/io/exr.h"

#include <exception>

#include <OpenEXR/ImfChannelList.h>
#include <OpenEXR/ImfFrameBuffer.h>
#include <OpenEXR/ImfHeader.h>
#include <OpenEXR/ImfInputFile.h>
#include <OpenEXR/ImfOutputFile.h>
#include <fmt/core.h>

#include "mvr/core/input_file.h"

namespace mvr {

Status writeDepthExr(const std::filesystem::path& path, int width, int height,
                     std::span<const float> distance) {
    if (width <= 0 || height <= 0 || distance.size() != std::size_t(width) * std::size_t(height)) {
        return usageError(fmt::format("{}: {} depth values for {}x{} pixels", path.string(),
                                      distance.size(), width, height));
    }
    try {
        Imf::Header header(width, height);
        header.channels().insert("Z", Imf::Channel(Imf::FLOAT));
        header.compression() = Imf::ZIP_COMPRESSION;
        Imf::OutputFile file(path.c_str(), header, 1);
        Imf::FrameBuffer frame;
        // OpenEXR's slices take a non-const base; writing only reads it.
        char* base = reinterpret_cast<char*>(const_cast<float*>(distance.data()));
        frame.insert("Z", Imf::Slice(Imf::FLOAT, base, sizeof(float),
                                     sizeof(float) * std::size_t(width)));
        file.setFrameBuffer(frame);
        file.writePixels(height);
    } catch (const std::exception& e) {
        return outputError(fmt::format("cannot write '{}': {}", path.string(), e.what()));
    }
    return {};
}

Result<ExrDepth> readDepthExr(const std::filesystem::path& path) {
    if (Status s = checkRegularFile(path, path.string()); !s) return s;
    try {
        Imf::InputFile file(path.c_str(), 1);
        const Imath::Box2i dw = file.header().dataWindow();
        if (!file.header().channels().findChannel("Z"))
            return inputError(fmt::format("{}: no \"Z\" channel", path.string()));
        ExrDepth out;
        out.width = dw.max.x - dw.min.x + 1;
        out.height = dw.max.y - dw.min.y + 1;
        out.distance.assign(std::size_t(out.width) * std::size_t(out.height), 0.0f);
        Imf::FrameBuffer frame;
        char* base = reinterpret_cast<char*>(out.distance.data()) -
                     (std::ptrdiff_t(dw.min.x) + std::ptrdiff_t(dw.min.y) * out.width) *
                         std::ptrdiff_t(sizeof(float));
        frame.insert("Z", Imf::Slice(Imf::FLOAT, base, sizeof(float),
                                     sizeof(float) * std::size_t(out.width)));
        file.setFrameBuffer(frame);
        file.readPixels(dw.min.y, dw.max.y);
        return out;
    } catch (const std::exception& e) {
        return inputError(fmt::format("{}: not a readable OpenEXR file ({})", path.string(),
                                      e.what()));
    }
}

}  // namespace mvr
