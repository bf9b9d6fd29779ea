#include "StatusReadout.hpp"

#include <QLabel>
#include <QStatusBar>

namespace kerf::ui {

StatusReadout::StatusReadout(QStatusBar* bar) : QObject(bar)
{
    voxels_ = new QLabel(bar);
    voxels_->setObjectName("status.voxels");
    memory_ = new QLabel(bar);
    memory_->setObjectName("status.memory");
    frame_ = new QLabel(bar);
    frame_->setObjectName("status.frame");
    device_ = new QLabel(bar);
    device_->setObjectName("status.device");
    for (QLabel* l : {voxels_, memory_, frame_, device_}) bar->addPermanentWidget(l);
    connect(bar, &QStatusBar::messageChanged, this, [this](const QString& message) {
        for (QLabel* l : {voxels_, memory_, frame_, device_}) l->setVisible(message.isEmpty());
    });
}

void StatusReadout::show(const VoxelizerProgress& p, const VoxelSnapshot* snap, const VoxelizerStats& s,
                         const qt::ViewportStatus& v, std::size_t memoryBudgetBytes, const GridLayout* gpuGrid)
{
    if (gpuGrid) {
        // The GPU builds the whole part: its preview, then full depth.
        if (v.gpuBusy)
            voxels_->setText(tr("Voxelizing on the GPU: %L1 tiles, depth %2").arg(gpuGrid->tileCount()).arg(gpuGrid->levels));
        else if (v.gpuVoxels)
            voxels_->setText(tr("Voxels (GPU%1): %L2 tiles, depth %3, %4 mm; built in %5 ms")
                                 .arg(v.shownComplete ? QString() : tr(", preview"))
                                 .arg(gpuGrid->tileCount())
                                 .arg(gpuGrid->levels)
                                 .arg(gpuGrid->voxelSize, 0, 'g', 3)
                                 .arg(v.gpuBuildMs, 0, 'f', 0));
        snap = nullptr; // the CPU's figures are not what is shown
    } else if (p.busy) {
        voxels_->setText(tr("Voxelizing: %1 %2 of %3 tiles (depth %4 of %5)")
                             .arg(p.coarsePass ? tr("coarse preview") : tr("refining"))
                             .arg(p.tilesBuilt)
                             .arg(p.tilesToBuild)
                             .arg(p.levels)
                             .arg(p.targetLevels));
    } else if (snap) {
        voxels_->setText(tr("Voxels: %L1 tiles, depth %2, %3 rebuilt; %4 mm")
                             .arg(snap->layout.tileCount())
                             .arg(snap->layout.levels)
                             .arg(s.dirtyTiles)
                             .arg(snap->layout.voxelSize, 0, 'g', 3));
    }
    QString memory = tr("%1: %2 MB%3")
                         .arg(v.vulkan ? tr("GPU") : tr("Voxels"))
                         .arg(double(v.voxelBytes) / 1e6, 0, 'f', 1)
                         .arg(v.streaming ? tr(" (streaming)") : QString());
    const bool overBudget = snap && snap->coarsenedForBudget > 0;
    if (overBudget)
        memory += tr(" — budget of %1 MB reached: %2 distant tiles coarsened")
                      .arg(memoryBudgetBytes >> 20)
                      .arg(snap->coarsenedForBudget);
    if (snap && snap->hiddenTiles > 0)
        memory += snap->hiddenTiles == 1 ? tr(" — 1 hidden tile kept coarse")
                                         : tr(" — %1 hidden tiles kept coarse").arg(snap->hiddenTiles);
    memory_->setText(memory);
    memory_->setStyleSheet(overBudget ? QStringLiteral("color: #b35900;") : QString());
    frame_->setText(v.traceMs >= 0.0 ? (v.bricks ? tr("Frame %1 ms, bricks %2 ms") : tr("Frame %1 ms, trace %2 ms"))
                                           .arg(v.frameMs, 0, 'f', 1)
                                           .arg(v.traceMs, 0, 'f', 1)
                                     : tr("Frame %1 ms").arg(v.frameMs, 0, 'f', 1));
    device_->setText(v.device);
    device_->setToolTip(v.fallbackReason);
}

} // namespace kerf::ui
