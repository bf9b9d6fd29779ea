#pragma once
// Connects the background voxelizer to the GUI thread: each version of the
// document is handed over at once (the voxelizer copies it and returns),
// and each publication arrives as a signal on the GUI thread, where the
// viewport takes it. The GUI thread never waits for voxelization.

#include "kerf/voxelizer/Voxelizer.hpp"

#include <QObject>

#include <deque>
#include <memory>
#include <mutex>

namespace kerf::ui {

class VoxelizerBridge : public QObject {
    Q_OBJECT
public:
    explicit VoxelizerBridge(QObject* parent = nullptr, VoxelizerOptions options = {});
    ~VoxelizerBridge() override;

    /// Queues a document version; returns its revision.
    std::uint64_t submit(const Document& doc);
    void setFocus(const glm::dvec3& point) { voxelizer_->setFocus(point); }
    void setView(std::optional<ViewRequirement> view) { voxelizer_->setView(std::move(view)); }
    void setOcclusion(std::shared_ptr<const OcclusionMap> picture) { voxelizer_->setOcclusion(std::move(picture)); }
    std::shared_ptr<const VoxelSnapshot> latest() const { return latest_; }
    VoxelizerStats lastStats() const { return voxelizer_->lastStats(); }
    VoxelizerProgress progress() const { return voxelizer_->progress(); }
    std::uint64_t lastSubmitted() const { return submitted_; }
    Voxelizer& voxelizer() { return *voxelizer_; }

signals:
    /// A publication (on the GUI thread).
    void published(std::shared_ptr<const kerf::VoxelSnapshot> snapshot);

private slots:
    /// On the GUI thread: hands the oldest publication in the mailbox on.
    void deliver();

private:
    std::mutex mailboxMutex_;
    std::deque<std::shared_ptr<const VoxelSnapshot>> mailbox_; // publications not yet delivered, oldest first
    std::unique_ptr<Voxelizer> voxelizer_;
    std::shared_ptr<const VoxelSnapshot> latest_;
    std::uint64_t submitted_ = 0;
};

} // namespace kerf::ui
