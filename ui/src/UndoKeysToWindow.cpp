#include "UndoKeysToWindow.hpp"

#include <QKeyEvent>
#include <QLineEdit>

namespace kerf::ui {

UndoKeysToWindow::UndoKeysToWindow(QLineEdit* edit) : QObject(edit), edit_(edit) {}

void UndoKeysToWindow::install(QLineEdit* edit, QWidget* owner)
{
    auto* filter = new UndoKeysToWindow(edit);
    edit->installEventFilter(filter);
    if (owner) owner->installEventFilter(filter);
}

bool UndoKeysToWindow::eventFilter(QObject*, QEvent* event)
{
    if (event->type() != QEvent::ShortcutOverride) return false;
    QLineEdit* edit = edit_;
    auto* key = static_cast<QKeyEvent*>(event);
    const bool undoKey = key->matches(QKeySequence::Undo) || key->matches(QKeySequence::Redo) ||
                         key->keyCombination() == QKeyCombination(Qt::ControlModifier | Qt::ShiftModifier, Qt::Key_Z) ||
                         key->keyCombination() == QKeyCombination(Qt::ControlModifier, Qt::Key_Y);
    if (!edit || !undoKey || edit->isModified()) return false;
    // Not overridden: the key goes on to the window's shortcuts.
    event->ignore();
    return true;
}

} // namespace kerf::ui
