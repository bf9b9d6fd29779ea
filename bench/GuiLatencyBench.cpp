// How calm the desktop application stays while a large part re-voxelizes
// (issue 6): the real main window, viewport and voxelizer, edits made
// through the document session exactly as the property editor makes them.
//
// For each edit it measures
//   - the longest time the GUI thread was blocked: a 1 ms timer on the GUI
//     thread records the largest gap between its ticks, from the edit until
//     the final picture is on screen (anything over a couple of ms is time
//     the event loop could not run);
//   - edit to coarse preview: until the viewport shows a snapshot of the
//     edited document (the coarse pass, streamed in);
//   - edit to final: until it shows that document at full depth.
// The first edit after opening is a warm-up and is not counted.
//
//   xvfb-run -a -s "-screen 0 1600x1000x24" build/bench/kerf_bench_gui [FILE.kerf] [--edits N]
//            [--feature-size MM] [--node ID] [--json OUT.json]
//
// Not a Google Benchmark: it needs the Qt event loop and a display.

#include "MainWindow.hpp"
#include "kerf/viewport/qt/ViewportWidget.hpp"

#include <QApplication>
#include <QElapsedTimer>
#include <QTest>
#include <QTimer>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

using namespace kerf;
using namespace kerf::ui;

namespace {

struct Sample {
    double applyMs = 0.0; // the edit itself on the GUI thread, with every view it updates
    double longestBlockMs = 0.0, coarseMs = 0.0, finalMs = 0.0;
    double voxelCoarseMs = 0.0, voxelFinalMs = 0.0; // the voxelizer's publications (before streaming and a frame)
};

double median(std::vector<double> v)
{
    std::sort(v.begin(), v.end());
    return v.empty() ? 0.0 : v[v.size() / 2];
}

} // namespace

int main(int argc, char** argv)
{
    QApplication app(argc, argv);
    QApplication::setApplicationName("Kerf bench");
    std::string file = std::string(KERF_EXAMPLES_DIR) + "/side-chair.kerf";
    std::string node = "dowel-hole-r", jsonOut;
    int edits = 8;
    double featureSize = 0.0;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto next = [&] { return i + 1 < argc ? std::string(argv[++i]) : std::string(); };
        if (a == "--edits") edits = std::stoi(next());
        else if (a == "--feature-size") featureSize = std::stod(next());
        else if (a == "--node") node = next();
        else if (a == "--json") jsonOut = next();
        else if (a.ends_with(".kerf")) file = a;
    }

    MainWindowOptions options;
    options.recoveryFolder = std::filesystem::temp_directory_path() / "kerf-bench-gui-recovery";
    options.askSave = [](const QString&) { return QMessageBox::Discard; };
    options.reportError = [](const QString&, const QString& m) { std::cerr << m.toStdString() << "\n"; };
    MainWindow window(options);
    window.resize(1280, 800);
    window.show();
    if (!window.openFile(file)) return 1;
    if (featureSize > 0.0)
        window.session()->apply("feature size", [&](Document& d) { d.settings.featureSize = featureSize; });
    qt::ViewportWidget* viewport = window.viewport();

    // The GUI thread's pulse: the largest gap between 1 ms ticks.
    QElapsedTimer clock;
    clock.start();
    qint64 lastTick = clock.nsecsElapsed();
    double longestGapMs = 0.0;
    QTimer pulse;
    pulse.setTimerType(Qt::PreciseTimer);
    pulse.setInterval(1);
    QObject::connect(&pulse, &QTimer::timeout, [&] {
        const qint64 now = clock.nsecsElapsed();
        longestGapMs = std::max(longestGapMs, double(now - lastTick) / 1e6);
        lastTick = now;
    });
    pulse.start();

    auto shownRevision = [&] { return viewport->status().shownRevision; };
    auto waitShown = [&](std::uint64_t revision, bool complete) {
        return QTest::qWaitFor(
            [&] {
                const auto s = viewport->status();
                return s.shownRevision >= revision && (!complete || (s.shownComplete && !s.streaming));
            },
            600000);
    };
    // The opened document, complete on screen.
    if (!waitShown(window.voxelizer()->lastSubmitted(), true)) return 1;
    const auto snap = window.voxelizer()->latest();
    std::fprintf(stderr, "%s: %ld tiles, %d levels, %.3g mm voxels; device %s\n", file.c_str(),
                 snap->layout.tileCount(), snap->layout.levels, snap->layout.voxelSize,
                 viewport->status().device.toStdString().c_str());

    // Baseline: the longest gap with nothing to do for two seconds (what
    // the machine's scheduling alone costs the GUI thread).
    longestGapMs = 0.0;
    lastTick = clock.nsecsElapsed();
    QTest::qWait(2000);
    const double idleGapMs = longestGapMs;
    std::fprintf(stderr, "idle: longest gap between 1 ms ticks %.1f ms\n", idleGapMs);

    std::vector<Sample> samples;
    for (int e = 0; e <= edits; ++e) {
        const double step = (e % 2 ? -3.0 : 3.0);
        longestGapMs = 0.0;
        lastTick = clock.nsecsElapsed();
        const qint64 t0 = clock.nsecsElapsed();
        const bool ok = window.session()->apply("move", [&](Document& d) {
            Node* n = d.root.find(node);
            if (!n) throw std::invalid_argument("no node " + node);
            n->transform.translate.x += step;
        });
        if (!ok) {
            std::cerr << "the edit was refused\n";
            return 1;
        }
        const double applyMs = double(clock.nsecsElapsed() - t0) / 1e6; // the edit and every handler it triggers
        const std::uint64_t revision = window.voxelizer()->lastSubmitted();
        if (!waitShown(revision, false)) return 1;
        const double coarse = double(clock.nsecsElapsed() - t0) / 1e6;
        if (!waitShown(revision, true)) return 1;
        const double final = double(clock.nsecsElapsed() - t0) / 1e6;
        (void)shownRevision;
        if (e == 0) continue; // warm-up
        const VoxelizerStats vs = window.voxelizer()->lastStats();
        samples.push_back({applyMs, longestGapMs, coarse, final, vs.coarseMs, vs.fineMs});
        std::fprintf(stderr,
                     "edit %d: the edit on the GUI thread %.1f ms, longest GUI block %.1f ms; on screen: coarse %.0f ms, "
                     "final %.0f ms; published: coarse %.1f ms, final %.1f ms (%zu tiles rebuilt)\n",
                     e, applyMs, longestGapMs, coarse, final, vs.coarseMs, vs.fineMs, vs.dirtyTiles);
    }
    std::vector<double> apply, block, coarse, final, voxelCoarse, voxelFinal;
    for (const auto& s : samples) {
        apply.push_back(s.applyMs);
        block.push_back(s.longestBlockMs);
        coarse.push_back(s.coarseMs);
        final.push_back(s.finalMs);
        voxelCoarse.push_back(s.voxelCoarseMs);
        voxelFinal.push_back(s.voxelFinalMs);
    }
    const double worstBlock = *std::max_element(block.begin(), block.end());
    std::printf("idle baseline (nothing happening): longest gap %.1f ms\n", idleGapMs);
    std::printf("edits: %zu\nthe edit on the GUI thread: median %.1f ms\nlongest GUI block: median %.1f ms, worst %.1f ms\n"
                "edit to coarse preview on screen: median %.0f ms\nedit to final on screen: median %.0f ms\n"
                "edit to coarse publication: median %.1f ms\nedit to final publication: median %.1f ms\n",
                samples.size(), median(apply), median(block), worstBlock, median(coarse), median(final), median(voxelCoarse),
                median(voxelFinal));
    if (!jsonOut.empty()) {
        nlohmann::ordered_json j;
        j["file"] = file;
        j["device"] = viewport->status().device.toStdString();
        j["tiles"] = snap->layout.tileCount();
        j["voxel_mm"] = snap->layout.voxelSize;
        j["edits"] = samples.size();
        j["idle_longest_gap_ms"] = idleGapMs;
        j["edit_on_gui_thread_median_ms"] = median(apply);
        j["gui_block_median_ms"] = median(block);
        j["gui_block_worst_ms"] = worstBlock;
        j["coarse_median_ms"] = median(coarse);
        j["final_median_ms"] = median(final);
        j["publication_coarse_median_ms"] = median(voxelCoarse);
        j["publication_final_median_ms"] = median(voxelFinal);
        std::ofstream(jsonOut) << j.dump(2) << "\n";
    }
    return 0;
}
