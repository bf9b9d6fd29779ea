#pragma once
// Ghosts of selected tools: a selected hole (any feature a difference takes
// away) has no surface of its own to tint, so its tool body is drawn
// translucent over the part. The body is meshed from the exact field of the
// feature alone (edit::documentOfNodeAlone, every array copy included) in
// the background; a newer selection cancels an older mesh. The same
// features changed while their ghosts are meshed (a gizmo drag, one edit
// per mouse move) do not cancel it: it is shown when done, and the latest
// of the changes is meshed next. Cancelled at every step, a dragged hole's
// ghost stayed where the drag began until the button was let go.

#include "kerf/document/Document.hpp"
#include "kerf/viewport/qt/ViewportWidget.hpp"

#include <QObject>

#include <atomic>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace kerf::ui {

class SelectionGhosts : public QObject {
    Q_OBJECT
public:
    explicit SelectionGhosts(qt::ViewportWidget* viewport, QObject* parent = nullptr);
    ~SelectionGhosts() override;

    /// Shows the ghosts of those of `ids` that the part subtracts (none:
    /// clears). Nothing is meshed again when those bodies did not change.
    void show(const Document& doc, const std::vector<std::string>& ids);
    /// Whether a ghost is still being meshed.
    bool busy() const { return pending_ > 0 || queued_; }

signals:
    /// The ghosts asked for last are in the viewport.
    void ready();
    /// Ghosts were put in the viewport (those asked for last, or an earlier
    /// version of the same features while they change).
    void shown();

private:
    void mesh(std::vector<Document> tools);

    qt::ViewportWidget* viewport_;
    std::shared_ptr<std::atomic<std::uint64_t>> generation_;
    int pending_ = 0;
    // The features whose ghosts are being meshed, and their latest version
    // asked for meanwhile (meshed next).
    std::optional<std::vector<std::string>> meshingIds_;
    std::optional<std::vector<Document>> queued_;
    // The tool bodies last asked for: an edit elsewhere in the part leaves
    // them as they are, and is not meshed again.
    std::vector<Document> shownTools_;
};

} // namespace kerf::ui
