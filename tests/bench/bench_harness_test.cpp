// The bench harness (tools/cli/bench/harness.h) on its own: statistics, how --methods lists
// become jobs (and the errors that name the entry), the order of interleaved batches, and one
// real measurement with the CPU backend on a tiny default scene. Nothing here checks a speed.
#include "bench/harness.h"

#include <gtest/gtest.h>

namespace mvr::cli::bench {
namespace {

TEST(BenchHarness, StatsInterpolateBetweenRanks) {
    const Stats s = statsOf({4.0, 1.0, 3.0, 2.0});
    EXPECT_EQ(s.n, 4);
    EXPECT_DOUBLE_EQ(s.median, 2.5);
    EXPECT_DOUBLE_EQ(s.q1, 1.75);
    EXPECT_DOUBLE_EQ(s.q3, 3.25);
    EXPECT_DOUBLE_EQ(s.min, 1.0);
    EXPECT_DOUBLE_EQ(s.max, 4.0);
    EXPECT_DOUBLE_EQ(statsOf({7.0}).median, 7.0);
    EXPECT_EQ(statsOf({}).n, 0);
    EXPECT_DOUBLE_EQ(quantile({}, 0.5), 0.0);
}

std::vector<std::string> texts(const std::vector<Job>& jobs) {
    std::vector<std::string> out;
    for (const Job& j : jobs) out.push_back(j.text());
    return out;
}

const JobRules kPaperRules{.addBaseline = true, .skipUnavailable = true, .allowAuto = false};

TEST(BenchHarness, PaperJobsGetTheirBaselineFirstAndOnce) {
    BackendSet backends({});
    std::vector<Skipped> skipped;
    auto jobs = resolveJobs({"soft:unified", "soft:multipass", "soft:unified"}, backends,
                            kPaperRules, &skipped);
    ASSERT_TRUE(jobs) << jobs.status().message();
    EXPECT_EQ(texts(*jobs), (std::vector<std::string>{"soft:multipass", "soft:unified"}));
    EXPECT_TRUE(skipped.empty());
    ASSERT_EQ(backends.made().size(), 1u);  // one backend for both jobs
    EXPECT_EQ((*jobs)[0].backend, (*jobs)[1].backend);
}

TEST(BenchHarness, PlainJobsStayAsGiven) {
    BackendSet backends({});
    auto jobs = resolveJobs({"soft:unified", "soft:unified"}, backends, {});
    ASSERT_TRUE(jobs) << jobs.status().message();
    EXPECT_EQ(texts(*jobs), (std::vector<std::string>{"soft:unified", "soft:unified"}));
    EXPECT_EQ(defaultMethodList(), (std::vector<std::string>{"soft:multipass", "soft:unified"}));
}

TEST(BenchHarness, BadEntriesNameTheOption) {
    auto message = [](const std::vector<std::string>& entries, const JobRules& rules) {
        BackendSet backends({});
        auto jobs = resolveJobs(entries, backends, rules);
        EXPECT_FALSE(jobs);
        EXPECT_EQ(jobs.status().code(), ErrorCode::Usage);
        return jobs.status().message();
    };
    EXPECT_EQ(message({"unified"}, {}),
              "--methods entry 'unified' is not of the form BACKEND:METHOD (e.g. soft:unified)");
    EXPECT_EQ(message({"soft:"}, {}),
              "--methods entry 'soft:' is not of the form BACKEND:METHOD (e.g. soft:unified)");
    EXPECT_EQ(message({"nope:multipass"}, kPaperRules)
                  .rfind("--methods entry 'nope:multipass': "
                         "unknown backend 'nope' (expected soft",
                         0),
              0u);
    EXPECT_EQ(message({"soft:bogus"}, {}),
              "--methods entry 'soft:bogus': unknown method 'bogus' of backend soft (expected one "
              "of: multipass, unified)");
    EXPECT_EQ(message({"soft:auto"}, kPaperRules),
              "--methods entry 'soft:auto': 'auto' is not a method to measure (it picks one of "
              "the others)");
    EXPECT_EQ(message({}, {}), "--methods is empty (expected e.g. soft:multipass,soft:unified)");
}

TEST(BenchHarness, ABadSimdPathNamesTheOption) {
    BackendSet backends({.threads = 0, .simd = "sse9"});
    auto soft = backends.get("soft");
    ASSERT_FALSE(soft);
    EXPECT_EQ(soft.status().message(),
              "--simd 'sse9' is not a SIMD path (expected auto, scalar, avx2 or avx512)");
}

TEST(BenchHarness, BatchesAlternateWhichGoesFirst) {
    std::string calls;
    const std::function<void()> fns[2] = {[&] { calls += 'a'; }, [&] { calls += 'b'; }};
    const std::vector<BatchSamples> t = measureBatches(fns, 3, 2);
    EXPECT_EQ(calls, "aabbbbaaaabb");
    ASSERT_EQ(t.size(), 2u);
    EXPECT_EQ(t[0].cpuMs.size(), 3u);
    EXPECT_EQ(t[1].wallMs.size(), 3u);
    EXPECT_EQ(repetitionsFor([] {}, 0.0), 1);
}

TEST(BenchHarness, MeasuresEveryJobEveryTimedRound) {
    SceneOptions scene;
    scene.size = "32x24";
    auto prepared = scene.prepare();
    ASSERT_TRUE(prepared) << prepared.status().message();
    BackendSet backends({.threads = 1});
    auto jobs = resolveJobs({"soft:multipass", "soft:unified"}, backends, {});
    ASSERT_TRUE(jobs) << jobs.status().message();
    const std::vector<Measured> m = measure(*jobs, *prepared, {.warmup = 1, .frames = 3});
    ASSERT_EQ(m.size(), 2u);
    for (std::size_t j = 0; j < m.size(); ++j) {
        EXPECT_FALSE(m[j].failed()) << m[j].error.message();
        EXPECT_EQ(m[j].wallMs.size(), 3u);
        EXPECT_EQ(m[j].cpuMs.size(), 3u);
        ASSERT_EQ(m[j].stats.size(), 3u);
        EXPECT_EQ(m[j].ran, (*jobs)[j].spec.method);
        EXPECT_EQ(m[j].stats[0].method, (*jobs)[j].spec.method);  // from Backend::lastStats()
        EXPECT_GT(m[j].wallMs[0], 0.0);
    }
    const Machine machine = describeMachine(backends);
    EXPECT_EQ(machine.threads, 1);
    EXPECT_EQ(machine.gpuRenderer, "not used");  // no GPU backend among the jobs
    EXPECT_FALSE(machine.backendInfo.empty());
    EXPECT_EQ(machine.backendInfo[0].rfind("soft: ", 0), 0u);
}

RenderStats frame(double draw, double readback, double gpu) {
    RenderStats s;
    s.drawWallMs = draw, s.readbackWallMs = readback, s.gpuMs = gpu;
    return s;
}

// A GPU backend's draw / readback / GPU timer: medians over the frames; a GPU timer sample that
// is negative (no timer) or above its own frame's draw time (llvmpipe's first GL_TIME_ELAPSED:
// 5.9e6 ms) is dropped; none left: no GPU time. A CPU backend's frames give nothing.
TEST(BenchHarness, DeviceTimesDropImpossibleGpuSamples) {
    const std::vector<RenderStats> frames = {frame(4.0, 1.0, 5.9e6), frame(2.0, 0.5, 1.5),
                                             frame(3.0, 0.7, -1.0), frame(5.0, 0.9, 4.5),
                                             frame(1.0, 0.6, 1.0)};
    const DeviceTimes d = deviceTimes(frames, true);
    EXPECT_TRUE(d.measured);
    EXPECT_DOUBLE_EQ(d.drawMs, 3.0);
    EXPECT_DOUBLE_EQ(d.readbackMs, 0.7);
    ASSERT_TRUE(d.gpuMs);
    EXPECT_DOUBLE_EQ(*d.gpuMs, 1.5);  // median of 1.5, 4.5, 1.0
    EXPECT_EQ(d.gpuFrames, 3);
    ASSERT_EQ(d.frameGpuMs.size(), frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i) {
        EXPECT_DOUBLE_EQ(d.frameDrawMs[i], frames[i].drawWallMs);
        if (d.frameGpuMs[i]) {
            EXPECT_LE(*d.frameGpuMs[i], d.frameDrawMs[i]);
        }
    }
    EXPECT_FALSE(d.frameGpuMs[0]);
    EXPECT_FALSE(d.frameGpuMs[2]);

    const DeviceTimes none = deviceTimes({frame(4.0, 1.0, 5.9e6), frame(2.0, 0.5, -1.0)}, true);
    EXPECT_TRUE(none.measured);
    EXPECT_FALSE(none.gpuMs);
    EXPECT_EQ(none.gpuFrames, 0);
    EXPECT_FALSE(deviceTimes(frames, false).measured);
}

// The shadows bench's K passes: one frame's parts summed; the GPU timer only if every part's is
// valid.
TEST(BenchHarness, SumStatsKeepsTheGpuTimerOnlyWhenEveryPartHasOne) {
    const RenderStats sum = sumStats({frame(2.0, 1.0, 1.5), frame(3.0, 0.5, 2.0)});
    EXPECT_DOUBLE_EQ(sum.drawWallMs, 5.0);
    EXPECT_DOUBLE_EQ(sum.readbackWallMs, 1.5);
    EXPECT_DOUBLE_EQ(sum.gpuMs, 3.5);
    EXPECT_TRUE(validGpuSample(sum));
    EXPECT_LT(sumStats({frame(2.0, 1.0, 1.5), frame(3.0, 0.5, 9e6)}).gpuMs, 0.0);
    EXPECT_LT(sumStats({frame(2.0, 1.0, -1.0), frame(3.0, 0.5, 2.0)}).gpuMs, 0.0);
}

// Which rows carry device times: a GPU row of the registry (or, for a backend that picks another
// one, the picked backend's, named in "BACKEND:METHOD").
TEST(BenchHarness, RanOnGpuFollowsTheRegistry) {
    const Job soft{.spec = {"soft", "unified"}, .backend = nullptr};
    EXPECT_FALSE(ranOnGpu(soft, "unified"));
    for (const BackendEntry& e : backends()) {
        const Job job{.spec = {e.name, "x"}, .backend = nullptr};
        EXPECT_EQ(ranOnGpu(job, "x"), e.gpu) << e.name;
        EXPECT_EQ(ranOnGpu(soft, e.name + ":x"), e.gpu) << e.name;
    }
}

}  // namespace
}  // namespace mvr::cli::bench
