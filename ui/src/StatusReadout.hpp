#pragma once
// The status bar's figures: the voxelization (its pass and progress, or the
// grid it finished), the voxel memory (and the budget's coarsening), the
// frame time and the device. A message shown in the bar takes the whole bar:
// the figures step aside while it shows, instead of cutting it off
// mid-sentence.

#include "kerf/viewport/qt/ViewportWidget.hpp"
#include "kerf/voxelizer/Voxelizer.hpp"

#include <QObject>

#include <cstddef>

class QLabel;
class QStatusBar;

namespace kerf::ui {

class StatusReadout : public QObject {
    Q_OBJECT
public:
    explicit StatusReadout(QStatusBar* bar);

    /// Shows the latest figures; `snapshot` may be null (nothing built yet).
    /// `gpuGrid`: the grid the GPU voxelizes on (null: the CPU voxelizes).
    void show(const VoxelizerProgress& progress, const VoxelSnapshot* snapshot, const VoxelizerStats& lastBuild,
              const qt::ViewportStatus& view, std::size_t memoryBudgetBytes, const GridLayout* gpuGrid = nullptr);

private:
    QLabel* voxels_;
    QLabel* memory_;
    QLabel* frame_;
    QLabel* device_;
};

} // namespace kerf::ui
