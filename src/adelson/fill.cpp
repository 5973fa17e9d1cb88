// Scan-line polygon fill, flat and Gouraud, single-eye and simultaneous (adelson1991
// "Rendering polygons"). The work is in scan.h.
#include "mvr/adelson/adelson.h"
#include "scan.h"

namespace mvr::adelson {

using detail::Count;
using detail::dispatch;
using detail::Mode;
using detail::scanFill;

void fillFlat(std::span<const double> x, std::span<const double> y, std::uint32_t color,
              Frame& frame, OpCounts* ops) {
    const double* xs[1] = {x.data()};
    Frame* frames[1] = {&frame};
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        scanFill<On, 1, Mode::Flat>(xs, y.data(), y.size(), nullptr, color, frames, n);
        n.flush(ops);
    });
}

void fillFlatStereo(const StereoPolygon& poly, std::uint32_t color, Frame& left, Frame& right,
                    OpCounts* ops) {
    const double* xs[2] = {poly.xl.data(), poly.xr.data()};
    Frame* frames[2] = {&left, &right};
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        scanFill<On, 2, Mode::Flat>(xs, poly.y.data(), poly.y.size(), nullptr, color, frames, n);
        n.flush(ops);
    });
}

namespace {
/// Vertex colors as double channels (thread-local buffers: no allocation per polygon).
struct Channels {
    const double* ptr[3];
    explicit Channels(std::span<const Rgb> c) {
        thread_local std::vector<double> r, g, b;
        r.clear(), g.clear(), b.clear();
        for (const Rgb& v : c) r.push_back(v.r), g.push_back(v.g), b.push_back(v.b);
        ptr[0] = r.data(), ptr[1] = g.data(), ptr[2] = b.data();
    }
};
}  // namespace

void fillGouraud(std::span<const double> x, std::span<const double> y, std::span<const Rgb> color,
                 Frame& frame, OpCounts* ops) {
    const Channels ch(color);
    const double* xs[1] = {x.data()};
    Frame* frames[1] = {&frame};
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        scanFill<On, 1, Mode::Gouraud>(xs, y.data(), y.size(), ch.ptr, 0u, frames, n);
        n.flush(ops);
    });
}

void fillGouraudStereo(const StereoPolygon& poly, Frame& left, Frame& right, OpCounts* ops) {
    const Channels ch(poly.color);
    const double* xs[2] = {poly.xl.data(), poly.xr.data()};
    Frame* frames[2] = {&left, &right};
    dispatch(ops, [&]<bool On>() {
        Count<On> n;
        scanFill<On, 2, Mode::Gouraud>(xs, poly.y.data(), poly.y.size(), ch.ptr, 0u, frames, n);
        n.flush(ops);
    });
}

}  // namespace mvr::adelson
