// mvr/adelson/adelson.h — adelson1991's simultaneous stereo algorithms on the CPU, each next
// to the single-eye algorithm it optimizes, with operation counters (the paper's measures I
// and II are stated in operation counts) so that `mvr bench adelson` can reproduce its Table 1.
//
// Conventions (the paper's, not the rest of mvr's): LEFT-handed object space, view plane at
// z = 0, centers of projection at (∓e/2, 0, −d) for the left / right eye. A point (x, y, z)
// projects to
//     x_left  = (x − z·e/(2d)) / (1 + z/d),   x_right = (x + z·e/(2d)) / (1 + z/d),
//     y       = y / (1 + z/d)  (the same for both eyes),   z_proj = z / (1 + z/d).
// Screen (pixel) coordinates: px = width/2 + x·scale, py = height/2 − y·scale (row 0 at the
// top, y down), pixel centers at (i + 0.5, j + 0.5). Fill rule: a pixel belongs to a span
// [xa, xb) when xa ≤ center < xb, scan-lines likewise in y: polygons that share an edge never
// share a pixel.
//
// Every "stereo" function gives exactly (bit for bit) what the matching single-eye function
// gives when run once per eye: the shared work (y, z, edge tables, top/bottom clipping,
// colors) is computed once with the same floating-point operations (this library is built
// with -ffp-contract=off). The one exception is the paper's own: BSP + one z-buffer draws the
// left eye by z-buffer instead of painter's order, so its left image can differ from the
// two-BSP-pass image where two surfaces are at the same depth (see renderBspZBuffer()).
//
// Operation counts: OpCounts, filled when a non-null pointer is passed (a compile-time
// specialization: the timing runs, with nullptr, pay nothing for the counting).
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

namespace mvr::adelson {

/// Counted operations. adelson1991 counts an addition, a multiplication and a comparison as
/// one unit each ("assuming that an addition takes the same amount of CPU time as a
/// multiplication"); divisions are counted with the multiplications as the paper does.
struct OpCounts {
    std::uint64_t adds = 0;     ///< additions and subtractions
    std::uint64_t muls = 0;     ///< multiplications and divisions
    std::uint64_t cmps = 0;     ///< comparisons that decide something (tests, sort steps)
    std::uint64_t interps = 0;  ///< incremental interpolation steps (x or a color channel)
    std::uint64_t total() const { return adds + muls + cmps; }
    OpCounts& operator+=(const OpCounts& o) {
        adds += o.adds, muls += o.muls, cmps += o.cmps, interps += o.interps;
        return *this;
    }
};

struct Vec3 {
    double x = 0, y = 0, z = 0;
};

/// The stereo camera of the paper plus the raster the images go to.
struct StereoCamera {
    double d = 2.0;    ///< distance from the centers of projection to the view plane (> 0)
    double e = 0.065;  ///< eye separation (≥ 0)
    int width = 640;   ///< pixels per eye image
    int height = 480;
    double scale = 400;  ///< pixels per view-plane unit
};

/// One projected point: x of the eye it was projected for (or both), shared y and z.
struct Projected {
    double x = 0, y = 0, z = 0;
};
struct ProjectedStereo {
    double xl = 0, xr = 0, y = 0, z = 0;
};

/// An RGBA8 image per eye (0xAABBGGRR), cleared to 0; `depth` is only used by z-buffering.
struct Frame {
    int width = 0, height = 0;
    std::vector<std::uint32_t> pixels;
    std::vector<float> depth;
    Frame() = default;
    Frame(int w, int h) : width(w), height(h), pixels(std::size_t(w) * h, 0u) {}
    void clear();
};

struct Rgb {
    float r = 0, g = 0, b = 0;  ///< [0, 1]
};
std::uint32_t packRgb(const Rgb& c);

// ---- perspective projection -----------------------------------------------------------------

/// Projects every point for one eye (eye = −1 left, +1 right), view-plane units.
/// Per point: 2 additions, 4 multiplications (the paper's count); `withZ`: also the projected
/// z = z / (1 + z/d) (one more multiplication; else out.z = 0).
void projectMono(std::span<const Vec3> points, int eye, const StereoCamera& cam,
                 std::span<Projected> out, OpCounts* ops = nullptr, bool withZ = false);
/// Both eyes at once: y, z and 1 + z/d once. Per point: 3 additions, 5 multiplications
/// (+1 for z, once for both eyes).
void projectStereo(std::span<const Vec3> points, const StereoCamera& cam,
                   std::span<ProjectedStereo> out, OpCounts* ops = nullptr, bool withZ = false);
/// View-plane units → pixel coordinates (see the header comment).
double toPixelX(double x, const StereoCamera& cam);
double toPixelY(double y, const StereoCamera& cam);

// ---- scan-line polygon fill (flat and Gouraud) ----------------------------------------------

/// A polygon in pixel coordinates for both eyes (shared y); `color` per vertex for Gouraud.
struct StereoPolygon {
    std::vector<double> xl, xr, y;
    std::vector<Rgb> color;
};

/// Scan-line fill (edge table sorted by y, active edge list, even-odd spans) of one eye's
/// polygon (x, y: pixel coordinates, any simple or self-intersecting polygon) in `color`.
void fillFlat(std::span<const double> x, std::span<const double> y, std::uint32_t color,
              Frame& frame, OpCounts* ops = nullptr);
/// Both eyes: the edge table and active edge list (y work) are shared; x, its increment and
/// the x order of the active edges are per eye.
void fillFlatStereo(const StereoPolygon& poly, std::uint32_t color, Frame& left, Frame& right,
                    OpCounts* ops = nullptr);
/// Gouraud: vertex colors interpolated along the edges (per scan-line: x and r, g, b — 4
/// interpolations) and across each span (r, g, b per interior pixel — 3 interpolations).
void fillGouraud(std::span<const double> x, std::span<const double> y, std::span<const Rgb> color,
                 Frame& frame, OpCounts* ops = nullptr);
/// Both eyes: edge colors are interpolated once (a vertex has the same color in both views
/// and an edge the same height), x per eye: 5 interpolations per edge scan-line for both eyes
/// instead of 8; interior pixels are still interpolated per eye.
void fillGouraudStereo(const StereoPolygon& poly, Frame& left, Frame& right,
                       OpCounts* ops = nullptr);

// ---- Liang–Barsky clipping --------------------------------------------------------------------

struct ClipWindow {
    double xmin = -1, xmax = 1, ymin = -1, ymax = 1;
};
struct Segment {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    bool visible = false;  ///< false: rejected (coordinates unspecified)
    bool operator==(const Segment&) const = default;
};
struct StereoSegment {
    double xl0 = 0, xr0 = 0, y0 = 0, xl1 = 0, xr1 = 0, y1 = 0;
};

/// Liang–Barsky line clipping of one segment against the 4 borders (bottom, top, left, right).
Segment clipLine(double x0, double y0, double x1, double y1, const ClipWindow& w,
                 OpCounts* ops = nullptr);
/// Both eyes: bottom and top once (the y equation is the same), left and right per eye —
/// 6 border tests instead of 8.
void clipLineStereo(const StereoSegment& s, const ClipWindow& w, Segment& left, Segment& right,
                    OpCounts* ops = nullptr);

/// Liang–Barsky polygon clipping (the turning-vertex algorithm as in Foley, van Dam, Feiner,
/// Hughes §3.14): output vertices appended to outX/outY (cleared first). Degenerate edges
/// along the window border are part of the algorithm's output.
void clipPolygon(std::span<const double> x, std::span<const double> y, const ClipWindow& w,
                 std::vector<double>& outX, std::vector<double>& outY, OpCounts* ops = nullptr);
/// Both eyes: only the y terms of each edge (Δy, entering/leaving y border, t_in_y, t_out_y)
/// are shared — the order of the border crossings differs between the eyes (paper Fig. 4).
void clipPolygonStereo(std::span<const double> xl, std::span<const double> xr,
                       std::span<const double> y, const ClipWindow& w, std::vector<double>& outXl,
                       std::vector<double>& outYl, std::vector<double>& outXr,
                       std::vector<double>& outYr, OpCounts* ops = nullptr);

// ---- back-face removal ------------------------------------------------------------------------

/// A polygon plane Ax + By + Cz + D = 0, normal (A, B, C) out of the front face, in the
/// RIGHT-eye data (the left-eye data is the right-eye data moved by −e in x: its plane is
/// (A, B, C, A·e + D)).
struct PlaneEq {
    double a = 0, b = 0, c = 0, d = 0;
};
/// One eye's back-face test: back when A·xv + B·yv + C·zv + D < 0 (3 mul, 3 add, 1 cmp each).
/// `planes` are that eye's planes. out[i] = 1 when back-facing.
void backFacesMono(std::span<const PlaneEq> planes, const Vec3& viewer, std::span<std::uint8_t> out,
                   OpCounts* ops = nullptr);
/// The paper's stereo classification from the right-eye planes: out[i] bit 0 = back for the
/// left eye, bit 1 = back for the right eye. Worst case 4 mul, 4 add, 3 cmp.
void backFacesStereo(std::span<const PlaneEq> planes, const Vec3& viewer, double e,
                     std::span<std::uint8_t> out, OpCounts* ops = nullptr);
/// The same classification without the paper's branches: both sign tests always (4 mul,
/// 4 add, 2 cmp). On a pipelined CPU the paper's data-dependent branches mispredict on mixed
/// input, which costs more than the arithmetic they save; this form vectorizes.
void backFacesStereoBranchFree(std::span<const PlaneEq> planes, const Vec3& viewer, double e,
                               std::span<std::uint8_t> out, OpCounts* ops = nullptr);

// ---- scenes: polygons in 3D -------------------------------------------------------------------

/// A convex planar polygon in object space (front face: counter-clockwise seen from the
/// front in the paper's left-handed space, normal = (v1 − v0) × (v2 − v0) pointing out of
/// it), a color per vertex (Gouraud; shadeVertices() computes them from `albedo`) and an id.
struct Polygon3 {
    std::vector<Vec3> v;
    std::vector<Rgb> color;
    Rgb albedo;
    std::uint32_t id = 0;
};
/// The plane of a polygon (unit normal from its first three vertices).
PlaneEq planeOf(const Polygon3& p);

/// adelson1991's test scene: a village of `buildings` houses (1..8; tessellated walls, gable
/// roofs, windows, a door, a chimney: 140 polygons each) on a 16-quad ground, 1136 polygons
/// for 8 buildings, in front of the view plane (z > 0). Vertex colors: shadeVertices().
std::vector<Polygon3> makeVillage(int buildings = 8);
/// Lambert's law with a point light and its distance, plus an ambient term, per vertex into
/// Polygon3::color (view independent: computed once for both eyes).
void shadeVertices(std::vector<Polygon3>& polys, OpCounts* ops = nullptr);
/// The camera framing the village.
StereoCamera villageCamera(int width = 640, int height = 480);

// ---- hidden-surface removal -------------------------------------------------------------------

/// A BSP tree of polygons (split where a plane cuts them).
struct BspTree {
    struct Node {
        std::uint32_t polygon = 0;  ///< index into polygons
        int front = -1, back = -1;
        PlaneEq plane;
    };
    std::vector<Polygon3> polygons;  ///< after splitting
    std::vector<Node> nodes;
    int root = -1;
};
BspTree buildBsp(std::vector<Polygon3> polygons);

/// Two passes through the BSP tree: back to front for each eye, flat fill in painter's
/// order (color = polygon id). `frame` cleared first.
void renderBspMono(const BspTree& tree, int eye, const StereoCamera& cam, Frame& frame,
                   OpCounts* ops = nullptr);
/// adelson1991's compromise: one pass back to front for the RIGHT eye, painting the right
/// image and z-buffering the left one (one z-buffer), both eyes filled from one edge table. Right image: identical to
/// renderBspMono(+1); left: the same visible surface except where two surfaces have the same
/// depth at a pixel center to within float precision (e.g. where a wall meets the ground).
void renderBspZBuffer(const BspTree& tree, const StereoCamera& cam, Frame& left, Frame& right,
                      OpCounts* ops = nullptr);

/// Scan-line hidden-surface removal (y-sorted edge list, active edges, per span the nearest
/// polygon at the span's center; no interpenetration). `gouraud`: vertex colors interpolated,
/// else the polygon's first vertex color. Projects the polygons itself (part of the work).
void renderScanlineMono(std::span<const Polygon3> polys, int eye, const StereoCamera& cam,
                        bool gouraud, Frame& frame, OpCounts* ops = nullptr);
/// Both eyes: one projection (y, z once), one y-sorted edge list and active edge list, the
/// edge z and edge colors once; x crossings, span order and interior pixels per eye.
void renderScanlineStereo(std::span<const Polygon3> polys, const StereoCamera& cam, bool gouraud,
                          Frame& left, Frame& right, OpCounts* ops = nullptr);

/// The paper's simple renderer: Lambert vertex colors + projection + scan-line hidden
/// surfaces + Gouraud, for one eye (the mono program, run once per eye) …
void renderVillageMono(std::vector<Polygon3>& polys, int eye, const StereoCamera& cam, Frame& frame,
                       OpCounts* ops = nullptr);
/// … and the stereo program (lighting once, simultaneous projection and scan-line).
void renderVillageStereo(std::vector<Polygon3>& polys, const StereoCamera& cam, Frame& left,
                         Frame& right, OpCounts* ops = nullptr);

// ---- the experiment (Table 1) -----------------------------------------------------------------

/// Savings of a simultaneous algorithm, from a cost of the two separate runs (`separate`,
/// left + right) and of the simultaneous run (`simultaneous`), in the paper's three measures:
///   I   = 1 − simultaneous / separate              (0 … 50 %)
///   II  = 1 − (simultaneous − separate/2) / (separate/2)   (cost of the second eye; 0 … 100 %)
///   III = separate / simultaneous                  (speed-up, 1 … 2)
/// (The paper's Table 1 prints III as 1 + II, e.g. 1.67 for I = 33 %; by its own definition
/// S = 1 / (1 − I) = 1.49 there. mvr reports S as defined.)
struct Savings {
    double measureI = 0, measureII = 0, measureIII = 0;
};
Savings savingsFrom(double separate, double simultaneous);

/// One measured case of a Table 1 row: the single-eye algorithm run for the left and the
/// right eye (`separate`) against the simultaneous one, on a workload built once.
struct ExperimentCase {
    std::string algorithm;                  ///< the Table 1 row, e.g. "Liang-Barsky line clipping"
    std::string caseName;                   ///< the workload, e.g. "200000 random segments"
    std::string label;                      ///< a short name for plots, e.g. "LB line clip"
    std::string paperI, paperII, paperIII;  ///< adelson1991 Table 1 as printed
    std::string opsNote;                    ///< what the operation counts cover
    /// Runs both eyes separately / simultaneously; counts into `ops` when non-null.
    std::function<void(OpCounts*)> separate, simultaneous;
    /// Runs both and compares their results: "" when they agree as the algorithm promises
    /// (bit for bit, or for BSP + z-buffer: identical right eye, left within the documented
    /// tie rule), else what differs. `detail` gets a short note (e.g. pixels compared).
    std::function<std::string(std::string& detail)> check;
};

/// The workloads of `mvr bench adelson`: every Table 1 row, some with several cases (polygon
/// sizes, scene sizes). `tiny`: small workloads for tests (milliseconds).
std::vector<ExperimentCase> adelsonCases(bool tiny);

}  // namespace mvr::adelson
