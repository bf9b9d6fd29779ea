// One progress and cancellation type for every long piece of work
// (kerf/document/Progress.hpp): its rules on their own, then each stage that
// takes it (the voxelizer, both tracers, the accuracy measures; the mesher's
// are in MesherTest) heard and stopped through it.

#include "kerf/accuracy/ExactVolume.hpp"
#include "kerf/accuracy/SurfaceDistance.hpp"
#include "kerf/document/Document.hpp"
#include "kerf/document/Progress.hpp"
#include "kerf/evaluator/TapeCompiler.hpp"
#include "kerf/mesher/MeshPart.hpp"
#include "kerf/tracer/Camera.hpp"
#include "kerf/tracer/ExactTracer.hpp"
#include "kerf/tracer/ReferenceTracer.hpp"
#include "kerf/voxelizer/Voxelize.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace kerf {
namespace {

TEST(Progress, ADefaultOneIsNeverCancelledAndReportsToNoOne)
{
    const Progress none;
    EXPECT_FALSE(none.cancelled());
    EXPECT_FALSE(none.reporting());
    none.report(0.5); // goes nowhere, harmlessly
    EXPECT_FALSE(none.stage(0.2, 0.4).cancelled());
}

TEST(Progress, ReportsAreClampedNonDecreasingSparseAndEndAtOne)
{
    std::vector<double> heard;
    const Progress p([&](double f) { heard.push_back(f); });
    EXPECT_TRUE(p.reporting());
    p.report(-1.0);
    for (int i = 0; i <= 10000; ++i) p.report(double(i) / 10000.0);
    p.report(0.3); // going back is not heard
    p.report(2.0);
    ASSERT_FALSE(heard.empty());
    EXPECT_EQ(heard.front(), 0.0);
    EXPECT_TRUE(std::is_sorted(heard.begin(), heard.end()));
    EXPECT_EQ(heard.back(), 1.0);
    EXPECT_EQ(std::count(heard.begin(), heard.end(), 1.0), 1);
    EXPECT_LE(heard.size(), 202u);
    EXPECT_GE(heard.size(), 150u);
}

TEST(Progress, AStageReportsIntoItsPartOfTheWhole)
{
    std::vector<double> heard;
    const Progress whole([&](double f) { heard.push_back(f); });
    const Progress second = whole.stage(0.5, 1.0);
    const Progress secondHalfOfIt = second.stage(0.5, 1.0);
    whole.stage(0.0, 0.5).report(1.0);
    secondHalfOfIt.report(0.0);
    secondHalfOfIt.report(1.0);
    EXPECT_EQ(heard, (std::vector<double>{0.5, 0.75, 1.0}));
}

TEST(Progress, CancellationLatchesAndAFurtherReasonStopsOnlyItsOwnWork)
{
    bool asked = false;
    const Progress work = Progress::cancelledWhen([&] { return asked; });
    bool deadline = false;
    const Progress probe = work.orCancelledWhen([&] { return deadline; });
    EXPECT_FALSE(work.cancelled());
    EXPECT_FALSE(probe.cancelled());
    deadline = true;
    EXPECT_TRUE(probe.cancelled());
    EXPECT_FALSE(work.cancelled()); // the deadline was the probe's alone
    deadline = false;
    EXPECT_TRUE(probe.cancelled()); // once stopped, stopped
    asked = true;
    EXPECT_TRUE(work.cancelled());
    EXPECT_TRUE(work.stage(0.0, 0.5).cancelled());
    asked = false;
    EXPECT_TRUE(work.cancelled());
    // The original's reasons reach the derived work.
    bool asked2 = false;
    const Progress other = Progress::cancelledWhen([&] { return asked2; });
    const Progress derived = other.orCancelledWhen([] { return false; });
    asked2 = true;
    EXPECT_TRUE(derived.cancelled());
}

TEST(Progress, ReportsFromManyThreadsReachTheCallbackOneAtATime)
{
    std::atomic<int> inside{0}, overlaps{0};
    int calls = 0;
    const Progress p([&](double) {
        if (++inside > 1) ++overlaps;
        ++calls; // unsynchronized on purpose: the type serializes
        std::this_thread::yield();
        --inside;
    });
    std::vector<std::thread> threads;
    for (int t = 0; t < 8; ++t)
        threads.emplace_back([&, t] {
            for (int i = 0; i < 2000; ++i) p.report(double(i * 8 + t) / 16000.0);
        });
    for (auto& t : threads) t.join();
    EXPECT_EQ(overlaps.load(), 0);
    EXPECT_GT(calls, 0);
}

// Each long stage: heard to the end, and stopped when asked.
class ProgressOfEveryStage : public ::testing::Test {
protected:
    const Document doc = Document::parse(R"({"format":"kerf","version":1,"root":{"id":"d","type":"difference","children":[
        {"id":"b","type":"box","size":[60,40,18],"round":2},
        {"id":"h","type":"cylinder","radius":5,"height":30}]}})",
                                         "progress.kerf");
    const Tape tape = compileTape(doc);
    const Camera camera = Camera::standardView(tape.bounds(), "iso", 96, 64);

    static Progress heardInto(std::vector<double>& heard)
    {
        return Progress([&heard](double f) { heard.push_back(f); });
    }
    static Progress stopped() { return Progress::cancelledWhen([] { return true; }); }
    static void expectHeardToTheEnd(const std::vector<double>& heard)
    {
        ASSERT_FALSE(heard.empty());
        EXPECT_TRUE(std::is_sorted(heard.begin(), heard.end()));
        EXPECT_EQ(heard.back(), 1.0);
    }
};

TEST_F(ProgressOfEveryStage, Voxelizer)
{
    const GridLayout layout = GridLayout::choose(tape.bounds(), 0.5);
    std::vector<double> heard;
    EXPECT_TRUE(voxelize(tape, layout, {}, heardInto(heard)).complete);
    expectHeardToTheEnd(heard);
    EXPECT_FALSE(voxelize(tape, layout, {}, stopped()).complete);
}

TEST_F(ProgressOfEveryStage, ExactTracer)
{
    std::vector<double> heard;
    EXPECT_TRUE(traceExact(tape, camera, 1e-3, 0, heardInto(heard)).complete);
    expectHeardToTheEnd(heard);
    const TraceImage none = traceExact(tape, camera, 1e-3, 0, stopped());
    EXPECT_FALSE(none.complete);
    EXPECT_EQ(std::count_if(none.depth.begin(), none.depth.end(), [](float d) { return std::isfinite(d); }), 0);
}

TEST_F(ProgressOfEveryStage, VoxelTracer)
{
    const FlatVoxelBuffers buffers =
        FlatVoxelBuffers::flatten(voxelize(tape, GridLayout::choose(tape.bounds(), 1.0)));
    std::vector<double> heard;
    EXPECT_TRUE(traceVoxels(buffers, camera, 0, {}, TraceQuality::Voxels, heardInto(heard)).complete);
    expectHeardToTheEnd(heard);
    EXPECT_FALSE(traceVoxels(buffers, camera, 0, {}, TraceQuality::Voxels, stopped()).complete);
}

TEST_F(ProgressOfEveryStage, ExactVolumeAndSurfaceDistance)
{
    std::vector<double> heard;
    EXPECT_TRUE(integrateVolume(tape, 1.0, 0, heardInto(heard)).complete);
    expectHeardToTheEnd(heard);
    EXPECT_FALSE(integrateVolume(tape, 1.0, 0, stopped()).complete);

    MeshOptions o;
    o.featureSize = 2.0;
    const std::optional<Mesh> mesh = meshTape(tape, o);
    ASSERT_TRUE(mesh.has_value());
    heard.clear();
    EXPECT_TRUE(measureSurfaceDistance(*mesh, tape, 0, heardInto(heard)).complete);
    expectHeardToTheEnd(heard);
    const SurfaceDistance none = measureSurfaceDistance(*mesh, tape, 0, stopped());
    EXPECT_FALSE(none.complete);
    EXPECT_EQ(none.samples, 0u);
}

} // namespace
} // namespace kerf
