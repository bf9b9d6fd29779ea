#pragma once
// The cut list: each visible body of the part with the stock it is cut
// from (length x width x thickness, mm, measured in the body's own frame by
// the tight-bounds search; evaluator/CutList.hpp) and how many, computed off
// the GUI thread; exportable as CSV (written atomically).

#include "kerf/document/Document.hpp"
#include "kerf/evaluator/CutList.hpp"

#include <QDialog>
#include <QFutureWatcher>

class QTableWidget;
class QLabel;
class QPushButton;

namespace kerf::ui {

class CutListDialog : public QDialog {
    Q_OBJECT
public:
    /// `suggestedFile`: where Export CSV… starts (beside the document, named after it).
    CutListDialog(const Document& doc, QString partName, QString suggestedFile, QWidget* parent = nullptr);

    /// Writes the list as CSV; false with a message in the dialog on failure.
    bool exportCsv(const QString& file);
    const std::vector<CutListRow>& rows() const { return rows_; }
    bool ready() const { return ready_; }

signals:
    void computed();

private:
    void showRows(std::vector<CutListRow> rows);

    QString partName_, suggestedFile_;
    QTableWidget* table_;
    QLabel* status_;
    QPushButton* exportButton_;
    QFutureWatcher<std::vector<CutListRow>> watcher_;
    std::vector<CutListRow> rows_;
    bool ready_ = false;
};

} // namespace kerf::ui
