#include "VoxelizerBridge.hpp"

#include <QMetaObject>

namespace kerf::ui {

VoxelizerBridge::VoxelizerBridge(QObject* parent, VoxelizerOptions options) : QObject(parent)
{
    qRegisterMetaType<std::shared_ptr<const kerf::VoxelSnapshot>>();
    options.onPublish = [this](std::shared_ptr<const VoxelSnapshot> snapshot) {
        // On the voxelizer's thread: the snapshot goes through a mailbox
        // guarded by a mutex of ours, and only a doorbell (no payload) goes
        // through Qt's event queue. The handover is then synchronized where
        // ThreadSanitizer can see it, not only inside Qt's own (uninstrumented)
        // locks. `this` outlives the thread: ~VoxelizerBridge destroys the
        // voxelizer, which joins it, before the QObject goes; a doorbell still
        // queued then is discarded with the object.
        {
            const std::lock_guard lock(mailboxMutex_);
            mailbox_.push_back(std::move(snapshot));
        }
        QMetaObject::invokeMethod(this, "deliver", Qt::QueuedConnection);
    };
    voxelizer_ = std::make_unique<Voxelizer>(std::move(options));
}

void VoxelizerBridge::deliver()
{
    std::shared_ptr<const VoxelSnapshot> snapshot;
    {
        const std::lock_guard lock(mailboxMutex_);
        if (mailbox_.empty()) return;
        snapshot = std::move(mailbox_.front());
        mailbox_.pop_front();
    }
    latest_ = snapshot;
    emit published(snapshot);
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
