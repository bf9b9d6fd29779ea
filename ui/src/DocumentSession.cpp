#include "DocumentSession.hpp"

#include "EditCommand.hpp"
#include "kerf/document/DocumentEdits.hpp"
#include "NodeText.hpp"
#include "kerf/document/DocumentError.hpp"

#include <QFileInfo>

namespace kerf::ui {

DocumentSession::DocumentSession(QObject* parent) : QObject(parent), document_(edit::emptyDocument())
{
    connect(&undo_, &QUndoStack::cleanChanged, this, &DocumentSession::stateChanged);
}

DocumentSession::~DocumentSession()
{
    // The undo stack signals a change of its clean state as it is destroyed,
    // after this object's own members are gone.
    undo_.disconnect(this);
}

QString DocumentSession::displayName() const
{
    return path_ ? QFileInfo(QString::fromStdString(path_->string())).fileName() : tr("Untitled");
}

namespace {

// The document after `edit`, resolved and validated as loading would; a
// refusal in the panels' words.
std::optional<Document> edited(const Document& document, const std::function<void(Document&)>& edit,
                               const std::optional<std::filesystem::path>& path, QString* error)
{
    Document after = document;
    try {
        edit(after);
        // With expressions, the edit is evaluated again: what refers to an
        // edited field or parameter follows it (and the parameters of a part
        // with no feature yet get their values). A document with an empty
        // root union is where every new part starts, and a file holds it.
        if (after.hasExpressions()) after = after.resolved(path ? path->string() : "");
        else after.validate(path ? path->string() : "");
    } catch (const DocumentError& e) {
        // Without the file name (the field is right there), and in the
        // panels' words: the feature's name and the field's row label.
        if (error) *error = describeRefusal(after.root, e.nodeId(), e.field(), e.reason());
        return std::nullopt;
    } catch (const std::exception& e) {
        if (error) *error = QString::fromUtf8(e.what());
        return std::nullopt;
    }
    return after;
}

} // namespace

bool DocumentSession::apply(const QString& text, const std::function<void(Document&)>& edit, QString* error,
                            const QString& mergeKey)
{
    if (previewing()) endPreview(true);
    std::optional<Document> after = edited(document_, edit, path_, error);
    if (!after) return false;
    if (*after == document_) return true; // nothing to undo
    undo_.push(new EditCommand(this, text, document_, std::move(*after), mergeKey));
    return true;
}

bool DocumentSession::preview(const QString& text, const std::function<void(Document&)>& edit, QString* error)
{
    std::optional<Document> after = edited(document_, edit, path_, error);
    if (!after) return false;
    if (!previewBefore_) previewBefore_ = document_;
    previewText_ = text;
    if (*after == document_) return true;
    document_ = std::move(*after);
    ++revision_;
    emit documentChanged();
    return true;
}

void DocumentSession::endPreview(bool keep)
{
    if (!previewBefore_) return;
    Document before = std::move(*previewBefore_);
    previewBefore_.reset();
    if (keep) {
        // Pushing runs the step's redo: the document it already is.
        if (!(before == document_))
            undo_.push(new EditCommand(this, previewText_, std::move(before), document_, QString()));
        return;
    }
    if (before == document_) return;
    document_ = std::move(before);
    ++revision_;
    emit documentChanged();
}

void DocumentSession::setDocumentFromCommand(const Document& doc)
{
    previewBefore_.reset(); // an undo or a redo during a preview: the command's document
    document_ = doc;
    ++revision_;
    emit documentChanged();
}

void DocumentSession::reset(Document doc, std::optional<std::filesystem::path> path, bool modified)
{
    document_ = std::move(doc);
    path_ = std::move(path);
    undo_.clear();
    undo_.setClean();
    modifiedWithoutUndo_ = modified;
    ++revision_;
    emit documentChanged();
    emit stateChanged();
}

void DocumentSession::saveAs(const std::filesystem::path& file)
{
    document_.save(file); // validates, writes atomically; throws and leaves everything as it was
    path_ = file;
    modifiedWithoutUndo_ = false;
    undo_.setClean();
    emit stateChanged();
}

} // namespace kerf::ui
