#pragma once
// Keeps a printable key typed in a table for the table: it starts editing
// the current cell (as typing over a spreadsheet cell does), where the
// window's one-key shortcuts would take it first ("1" the front view, "f"
// Fit All, "5" orthographic), since an item view does not claim the keys it
// edits with.

#include <QObject>

class QAbstractItemView;

namespace kerf::ui {

class TypingStaysInTable : public QObject {
public:
    /// Watches `table`; owned by it.
    static void install(QAbstractItemView* table);

protected:
    bool eventFilter(QObject* watched, QEvent* event) override;

private:
    explicit TypingStaysInTable(QObject* parent) : QObject(parent) {}
};

} // namespace kerf::ui
