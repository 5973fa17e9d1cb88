// src/io/jpeg_errors.h — libjpeg's error handling as mvr's JPEG code uses it: the decoder here
// (src/io/jpeg.cpp) and the encoder and JPS / MPO files of mvr::composite (src/composite/jpeg.cpp,
// which has src/io on its private include path). Needs <jpeglib.h> (libjpeg-turbo).
//
// libjpeg reports fatal errors through error_exit, which must not return: onJpegError longjmps
// back to the setjmp in the calling function. Everything that lives across the setjmp is heap
// state owned by a unique_ptr created before it, so no C++ object is skipped or left
// indeterminate. Warnings (corrupt data, premature end of file) are recorded: libjpeg would
// otherwise hand back a gray-filled picture, and mvr refuses to return a silently wrong image.
#pragma once

#include <csetjmp>
#include <cstdio>

#include <jpeglib.h>

namespace mvr::detail {

struct JpegErrors {
    jpeg_error_mgr pub{};
    std::jmp_buf jump{};
    char message[JMSG_LENGTH_MAX] = {};
    char warning[JMSG_LENGTH_MAX] = {};
    int warnings = 0;
};

[[noreturn]] inline void onJpegError(j_common_ptr cinfo) {
    auto* err = reinterpret_cast<JpegErrors*>(cinfo->err);
    (*cinfo->err->format_message)(cinfo, err->message);
    std::longjmp(err->jump, 1);
}

inline void onJpegMessage(j_common_ptr cinfo, int level) {
    if (level >= 0) return;  // trace messages
    auto* err = reinterpret_cast<JpegErrors*>(cinfo->err);
    if (err->warnings++ == 0) (*cinfo->err->format_message)(cinfo, err->warning);
}

/// Points `err` at libjpeg's defaults with mvr's error_exit and emit_message.
inline void installJpegErrors(JpegErrors& err) {
    jpeg_std_error(&err.pub);
    err.pub.error_exit = onJpegError;
    err.pub.emit_message = onJpegMessage;
}

}  // namespace mvr::detail
