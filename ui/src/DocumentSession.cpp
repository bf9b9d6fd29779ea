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

bool DocumentSession::apply(const QString& text, const std::function<void(Document&)>& edit, QString* error,
                            const QString& mergeKey)
{
    Document after = document_;
    try {
        edit(after);
        // With expressions, the edit is evaluated again: what refers to an
        // edited field or parameter follows it (and the parameters of a part
        // with no feature yet get their values). A document with an empty
        // root union is where every new part starts, and a file holds it.
        if (after.hasExpressions()) after = after.resolved(path_ ? path_->string() : "");
        else after.validate(path_ ? path_->string() : "");
    } catch (const DocumentError& e) {
        // Without the file name (the field is right there), and in the
        // panels' words: the feature's name and the field's row label.
        if (error) *error = describeRefusal(after.root, e.nodeId(), e.field(), e.reason());
        return false;
    } catch (const std::exception& e) {
        if (error) *error = QString::fromUtf8(e.what());
        return false;
    }
    if (after == document_) return true; // nothing to undo
    undo_.push(new EditCommand(this, text, document_, std::move(after), mergeKey));
    return true;
}

void DocumentSession::setDocumentFromCommand(const Document& doc)
{
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
