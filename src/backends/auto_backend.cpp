// The "auto" backend: picks the fastest BACKEND:METHOD for a request on this machine, the way
// gl's own "auto" method picks among gl's methods (src/gl/renderer.cpp renderAuto), one level
// up. The candidates are every registered backend (soft, gl where it is built and runs here,
// rows added with registerBackend()) with its default method, that backend's fastest exact one
// (soft: unified; gl: auto, which measures gl's exact methods itself: the candidate is then the
// method it picked). Each candidate renders the first frame of a kind of request three times:
// one warm-up (compiles, allocates; gl:auto measures its own methods in it), then the best of
// two renders timed by wall clock around render(). The fastest wins (equal times: registry
// order); the choice is kept for every later frame of the same kind (a sequence's frames), so
// they cost one render of the chosen backend:method each.
//
// A kind of request: view count, size, shading, culling, wireframe, shadows (map size), and the
// scene's size (triangles, instances, meshes, textures, lights) — not the cameras, so that an
// orbit or a moving rig keeps its choice.
#include "auto_backend.h"

#include <algorithm>
#include <chrono>
#include <map>

#include <fmt/format.h>

namespace mvr::detail {

namespace {

using Clock = std::chrono::steady_clock;

class AutoBackend final : public Backend {
public:
    explicit AutoBackend(BackendOptions options) : mOptions(std::move(options)) {}

    std::string name() const override { return kAutoBackend; }
    std::vector<std::string> methods() const override { return {kAutoBackend}; }
    std::string defaultMethod() const override { return kAutoBackend; }

    Status supports(const std::string& method) const override {
        if (method == kAutoBackend) return Status::ok();
        return usageError(fmt::format(
            "backend auto has one method, auto (it measures each backend's default method and "
            "picks the fastest); for method '{}' name its backend (--backend {} --method {})",
            method, fmt::join(backendNames(), "|"), method));
    }

    Result<RenderOutput> render(const Scene& scene, const Rig& rig, const RenderSettings& settings,
                                const std::string& method) override {
        return renderThroughInto(*this, scene, rig, settings, method);
    }

    Status renderInto(const Scene& scene, const Rig& rig, const RenderSettings& settings,
                      const std::string& method, RenderOutput& out) override {
        if (Status s = validateRequest(scene, rig, settings); !s) return s;
        if (Status s = supports(method); !s) return s;
        const std::string key = requestKey(scene, rig, settings);
        auto it = mChoices.find(key);
        if (it == mChoices.end()) {
            // The first frame of this kind: measure, and return the winner's last frame.
            auto choice = choose(scene, rig, settings, out);
            if (!choice) return choice.status();
            it = mChoices.emplace(key, std::move(choice).value()).first;
            if (!settings.output) return finish(it->second, out);
            // The caller's memory (OutputBlock) was kept out of the measuring renders: the
            // returned frame is one more render of the winner into it.
        }
        const Choice& c = it->second;
        if (Status s = c.candidate->backend->renderInto(scene, rig, settings, c.method, out); !s)
            return s;
        return finish(c, out);
    }

    std::vector<std::string> info() const override {
        std::vector<std::string> lines{
            "picks the fastest BACKEND:METHOD for each kind of request (view count, size, "
            "shading, scene size): each backend's default method measured on the first frame "
            "(one warm-up, then the best of two renders), the choice kept for later frames",
            fmt::format("candidates: {}", fmt::join(backendNames(), ", ")), "method: auto only"};
        return lines;
    }

    std::optional<RenderStats> lastStats() const override { return mLastStats; }

private:
    struct Candidate {
        std::string name;
        std::unique_ptr<Backend> backend;  ///< null: could not be made (`why`)
        std::string why;
    };
    struct Choice {
        Candidate* candidate = nullptr;
        std::string method;  ///< the candidate's method (gl: the one its auto picked)
        std::string note;
    };

    static std::string requestKey(const Scene& scene, const Rig& rig, const RenderSettings& s) {
        return fmt::format("{}/{}x{}/{}/{}{}/{}/{}:{}/{}/{}/{}/{}/{}", rig.viewCount(), s.width,
                           s.height, shadingName(s.shading), s.cullBackFaces, s.wireframe,
                           int(s.specular),
                           s.shadows, s.shadows ? s.shadowMapSize : 0, scene.triangleCount(),
                           scene.instances.size(), scene.meshes.size(), scene.textures.size(),
                           scene.lights.size());
    }

    /// The registry's backends, made once (with this backend's options).
    void makeCandidates() {
        if (!mCandidates.empty()) return;
        for (const BackendEntry& e : backends()) {
            Candidate c{e.name, nullptr, {}};
            auto made = e.make(mOptions);
            if (made) {
                c.backend = std::move(made).value();
            } else {
                // A backend that refuses this backend's CPU options: made without them.
                auto plain = e.make({});
                if (plain) {
                    c.backend = std::move(plain).value();
                } else {
                    c.why = made.status().message();
                }
            }
            mCandidates.push_back(std::move(c));
        }
    }

    Result<Choice> choose(const Scene& scene, const Rig& rig, const RenderSettings& given,
                          RenderOutput& out) {
        makeCandidates();
        RenderSettings s = given;
        s.output = nullptr;  // measuring renders use their own memory
        struct Measured {
            double ms;
            std::size_t index;  ///< into mCandidates (the registry's order)
            std::string method;
            RenderOutput frame;  ///< its last render
        };
        std::vector<Measured> times;
        std::vector<std::string> skipped;
        for (std::size_t i = 0; i < mCandidates.size(); ++i) {
            Candidate& c = mCandidates[i];
            if (!c.backend) {
                skipped.push_back(fmt::format("{} ({})", c.name, c.why));
                continue;
            }
            std::string method = c.backend->defaultMethod();
            if (Status st = c.backend->supports(method); !st) {
                skipped.push_back(fmt::format("{} ({})", c.name, st.message()));
                continue;
            }
            // One warm-up, then the best of two. A backend whose default method picks one of
            // its own (gl: auto) measures its methods in the warm-up: the candidate is its pick.
            RenderOutput frame;
            double best = 1e300;
            Status error = Status::ok();
            for (int run = 0; run < 3; ++run) {
                const auto t0 = Clock::now();
                error = c.backend->renderInto(scene, rig, s, method, frame);
                const double ms =
                    std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
                if (!error) break;
                if (run == 0) {
                    if (!frame.method.empty()) method = frame.method;
                    continue;
                }
                best = std::min(best, ms);
            }
            if (!error) {
                skipped.push_back(fmt::format("{}:{} ({})", c.name, method, error.message()));
                continue;
            }
            times.push_back({best, i, method, std::move(frame)});
        }
        if (times.empty()) {
            return unsupportedError(
                fmt::format("auto: no backend can render this here: {}", fmt::join(skipped, ", ")));
        }
        std::stable_sort(times.begin(), times.end(),
                         [](const Measured& a, const Measured& b) { return a.ms < b.ms; });
        std::vector<std::string> parts;
        for (const Measured& m : times) {
            parts.push_back(
                fmt::format("{}:{} {:.2f} ms", mCandidates[m.index].name, m.method, m.ms));
        }
        Choice c;
        c.candidate = &mCandidates[times.front().index];
        c.method = times.front().method;
        c.note = fmt::format(
            "auto picked {}:{}: fastest of each backend's default method for {} view{} at {}x{}, "
            "{} shading (best of two renders after a warm-up: {}){}",
            c.candidate->name, c.method, rig.viewCount(), rig.viewCount() == 1 ? "" : "s", s.width,
            s.height, shadingName(s.shading), fmt::join(parts, ", "),
            skipped.empty() ? "" : fmt::format("; skipped: {}", fmt::join(skipped, ", ")));
        // The winner's last frame is the one returned (its backend's lastStats() are that
        // frame's: each candidate's renders run back to back).
        out = std::move(times.front().frame);
        return c;
    }

    /// Names the choice in the output and keeps the chosen backend's stats of this frame.
    Status finish(const Choice& c, RenderOutput& out) {
        out.method = c.candidate->name + ":" + (out.method.empty() ? c.method : out.method);
        out.note = c.note;
        mLastStats = c.candidate->backend->lastStats();
        if (mLastStats) {
            mLastStats->method = out.method;
        } else {
            mLastStats = RenderStats{};
            mLastStats->method = out.method;
        }
        return Status::ok();
    }

    BackendOptions mOptions;
    std::vector<Candidate> mCandidates;  ///< pointers into it are kept: made once, never grown
    std::map<std::string, Choice> mChoices;
    std::optional<RenderStats> mLastStats;
};

}  // namespace

std::unique_ptr<Backend> makeAutoBackend(const BackendOptions& options) {
    return std::make_unique<AutoBackend>(options);
}

}  // namespace mvr::detail
