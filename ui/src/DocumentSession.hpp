#pragma once
// The open document as the application edits it: the feature tree, the
// file it came from, the undo stack, whether it is modified. Every change
// goes through apply(), which builds the edited copy, validates it exactly
// as loading would (Document::validate) and only then pushes it as an
// undoable command; a refused edit changes nothing and says why.
//
// Undo stores whole documents (before, after): furniture parts are small
// (hundreds of nodes), and a snapshot can never replay differently.
// Consecutive edits of one field (a dragged value) merge into one command.

#include "kerf/document/Document.hpp"

#include <QObject>
#include <QString>
#include <QUndoStack>

#include <filesystem>
#include <functional>
#include <optional>

namespace kerf::ui {

class DocumentSession : public QObject {
    Q_OBJECT
public:
    explicit DocumentSession(QObject* parent = nullptr);
    ~DocumentSession() override;

    const Document& document() const { return document_; }
    /// Increases with every change of the document (edits, undo, redo, open).
    std::uint64_t revision() const { return revision_; }
    QUndoStack* undoStack() { return &undo_; }

    /// The file the document was loaded from or last saved to (none for a new one).
    const std::optional<std::filesystem::path>& path() const { return path_; }
    bool isModified() const { return !undo_.isClean() || modifiedWithoutUndo_; }
    /// A name for the window title: the file name or "Untitled".
    QString displayName() const;

    /// Applies `edit` to a copy of the document and, when the result is
    /// valid, pushes it as an undoable command named `text`. Edits with the
    /// same `mergeKey` (non-empty) in a row merge into one command. Returns
    /// false with `error` set (one line naming node and field) when the edit
    /// throws or the result would not load; the document is then unchanged.
    bool apply(const QString& text, const std::function<void(Document&)>& edit, QString* error = nullptr,
               const QString& mergeKey = {});

    /// Shows an edit under way (a gizmo drag, one call per mouse move) as
    /// the document, validated as apply() does, without an undo step yet:
    /// endPreview() makes the edits since the first preview one step, or
    /// takes them back. A drag's steps once went on the undo stack as they
    /// came, and the first cleared what Redo had, even when Esc then took
    /// the drag back. Any other change (an edit, an undo) ends the preview:
    /// apply() keeps it as a step first, an undo or redo drops it.
    bool preview(const QString& text, const std::function<void(Document&)>& edit, QString* error = nullptr);
    void endPreview(bool keep);
    bool previewing() const { return previewBefore_.has_value(); }

    /// Replaces the document (New, Open, recovery). Clears the undo stack.
    /// `modified`: the document differs from the file (a recovered autosave).
    void reset(Document doc, std::optional<std::filesystem::path> path, bool modified = false);
    /// Saves atomically to `file` and makes it the document's path. Throws
    /// DocumentError with the reason; the document and its file stay as they were.
    void saveAs(const std::filesystem::path& file);

signals:
    /// The document changed (any way): views refresh from document().
    void documentChanged();
    /// The modified state or the path changed: the title refreshes.
    void stateChanged();

private:
    friend class EditCommand;
    void setDocumentFromCommand(const Document& doc);

    Document document_;
    std::uint64_t revision_ = 0;
    std::optional<std::filesystem::path> path_;
    QUndoStack undo_;
    bool modifiedWithoutUndo_ = false;
    // The document before the preview under way, and the step's name.
    std::optional<Document> previewBefore_;
    QString previewText_;
};

} // namespace kerf::ui
