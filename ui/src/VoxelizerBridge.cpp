#include "VoxelizerBridge.hpp"

#include <QMetaObject>
#include <QPointer>

namespace kerf::ui {

VoxelizerBridge::VoxelizerBridge(QObject* parent, VoxelizerOptions options) : QObject(parent)
{
    qRegisterMetaType<std::shared_ptr<const kerf::VoxelSnapshot>>();
    QPointer<VoxelizerBridge> self(this);
    options.onPublish = [self](std::shared_ptr<const VoxelSnapshot> snapshot) {
        // On the voxelizer's thread: hand over to the GUI thread.
        QMetaObject::invokeMethod(
            self.data(),
            [self, snapshot] {
                if (!self) return;
                self->latest_ = snapshot;
                emit self->published(snapshot);
            },
            Qt::QueuedConnection);
    };
    voxelizer_ = std::make_unique<Voxelizer>(std::move(options));
}

// The voxelizer's destructor cancels its work and waits; a publication
// queued meanwhile finds `self` gone and is dropped.
VoxelizerBridge::~VoxelizerBridge() = default;

std::uint64_t VoxelizerBridge::submit(const Document& doc)
{
    submitted_ = voxelizer_->setDocument(doc);
    return submitted_;
}

} // namespace kerf::ui
