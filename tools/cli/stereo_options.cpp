#include "stereo_options.h"

#include <fmt/core.h>

namespace mvr::cli {

void StereoSurfaceOptions::addTo(CLI::App* app) {
    app->add_option("--sky", sky,
                    "Sky at infinity behind everything, with each view's stereo projection "
                    "(parallax = the separation): 'gradient', 'environment' (the --environment "
                    "map), or a PNG/JPEG map or an HDR one (.hdr, .exr: exposed and tone mapped "
                    "as the scene): equirectangular (2:1, centre column looks down -Z) or a "
                    "horizontal cube cross (4:3: +Y above; -X -Z +X +Z; -Y below). Needs a "
                    "depth buffer");
    app->add_flag("--floating-window", floatingWindow,
                  "Black out, per view, the strip at the left/right frame edge where an object "
                  "nearer than the screen is seen by one eye only (width from the rig and the "
                  "nearest such depth). Off-axis rigs; needs a depth buffer");
    app->add_option("--letterbox", letterbox,
                    "Two black bands, each this percentage of the height, at the convergence depth "
                    "(out-of-screen objects overdraw them). Needs a depth buffer");
    app->add_option("--label", labels,
                    "Text at a depth: 'TEXT@x,y[,distance]', x,y fractions of the view (0,0 = top "
                    "left), distance = eye-space distance (default: the convergence, on the "
                    "screen); parallax = separation x (1 - convergence/distance); repeatable")
        ->type_name("TEXT@x,y[,d]");
    app->add_option("--label-anchor", anchors,
                    "Text attached to a 3D anchor point: 'TEXT@X,Y,Z' (world units); repeatable")
        ->type_name("TEXT@X,Y,Z");
    app->add_option("--angular-aa", angularAA,
                    "Angular anti-aliasing (Zwicker et al. 2006): after rendering, blur each view "
                    "per pixel by a box as wide as the point's parallax step between adjacent "
                    "views beyond one pixel, times S (horizontal; also vertical for a view grid), "
                    "so the focal plane stays sharp and far content stops jumping between views. "
                    "auto (default): on (S 1) for a multi-view display (a --display preset with a "
                    "view cone, --view-cone), off for other renders and the benches; off; or S > "
                    "0. Off-axis rigs of 2+ views; CPU, after read-back on every backend "
                    "(docs/displays.md)")
        ->type_name("auto|off|S");
}

}  // namespace mvr::cli
