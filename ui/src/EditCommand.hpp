#pragma once
// One undoable edit: the document before and after. Merges with the next
// edit of the same key (a value dragged or stepped with the arrows), keeping
// the first "before" and the last "after".

#include "kerf/document/Document.hpp"

#include <QUndoCommand>

namespace kerf::ui {

class DocumentSession;

class EditCommand : public QUndoCommand {
public:
    EditCommand(DocumentSession* session, const QString& text, Document before, Document after, QString mergeKey);

    void undo() override;
    void redo() override;
    int id() const override { return mergeKey_.isEmpty() ? -1 : kMergeableId; }
    bool mergeWith(const QUndoCommand* other) override;

private:
    static constexpr int kMergeableId = 0x4b657266; // "Kerf"
    DocumentSession* session_;
    Document before_, after_;
    QString mergeKey_;
};

} // namespace kerf::ui
