#pragma once
// Lets Undo and Redo reach the window from a text field that has nothing of
// its own to undo. A QLineEdit claims Ctrl+Z for its own typing; once a value
// is committed (Enter, or the field re-shown from the document), that typing
// history is empty, and Ctrl+Z pressed with the field still focused would do
// nothing at all. While the field holds uncommitted typing, Ctrl+Z still
// undoes that typing, as in any text field.

#include <QObject>

class QLineEdit;
class QWidget;

namespace kerf::ui {

class UndoKeysToWindow : public QObject {
public:
    /// Watches `edit`, and `owner` too where the edit is part of another
    /// widget (a spin box's line edit); owned by `edit`.
    static void install(QLineEdit* edit, QWidget* owner = nullptr);

protected:
    bool eventFilter(QObject* watched, QEvent* event) override;

private:
    explicit UndoKeysToWindow(QLineEdit* edit);
    QLineEdit* edit_;
};

} // namespace kerf::ui
