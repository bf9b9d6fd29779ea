#include "EditCommand.hpp"

#include "DocumentSession.hpp"

namespace kerf::ui {

EditCommand::EditCommand(DocumentSession* session, const QString& text, Document before, Document after,
                         QString mergeKey)
    : QUndoCommand(text), session_(session), before_(std::move(before)), after_(std::move(after)),
      mergeKey_(std::move(mergeKey))
{
}

void EditCommand::undo() { session_->setDocumentFromCommand(before_); }
void EditCommand::redo() { session_->setDocumentFromCommand(after_); }

bool EditCommand::mergeWith(const QUndoCommand* other)
{
    const auto* o = dynamic_cast<const EditCommand*>(other);
    if (!o || o->mergeKey_ != mergeKey_) return false;
    after_ = o->after_;
    setText(o->text()); // the step says where the drag ended
    // A drag that came back to where it began leaves no step (QUndoStack
    // deletes an obsolete command after merging).
    setObsolete(after_ == before_);
    return true;
}

} // namespace kerf::ui
