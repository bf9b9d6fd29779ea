#pragma once
// The Parameters panel: the document's named parameters as a table (name,
// expression, value, comment). Editing a name renames the parameter and
// every expression that uses it; editing an expression re-evaluates the
// document, so that every feature that depends on it follows; Add and
// Delete (refused while an expression uses the parameter, saying where).
// Every change is one undo step through the DocumentSession; a refusal is
// said under the table, in the words of the document's own messages, and
// the table shows the document as it stays.

#include "kerf/document/Document.hpp"

#include <QWidget>

#include <functional>
#include <string>
#include <vector>

class QLabel;
class QPushButton;
class QTableWidget;
class QTableWidgetItem;

namespace kerf::ui {

class DocumentSession;

class ParametersPanel : public QWidget {
    Q_OBJECT
public:
    enum Column { NameColumn, ExpressionColumn, ValueColumn, CommentColumn };

    explicit ParametersPanel(DocumentSession* session, QWidget* parent = nullptr);

    QTableWidget* table() const { return table_; }

protected:
    /// Delete (or Backspace) with the table in focus removes the selected
    /// parameter: the window's Delete, which deletes the selected feature,
    /// does not fire there (a newcomer lost the table top that way). Esc
    /// there takes a refusal's message away.
    bool eventFilter(QObject* watched, QEvent* event) override;

public:
    /// The refusal shown under the table ("" when none).
    QString error() const;

    /// Adds a parameter ("p", "p2", ...) and starts editing its name.
    void addParameter();
    /// Removes the selected parameter (refused while it is used).
    void removeSelected();

private:
    /// "Size X of Side panel, Position Z of the cylinder and 3 more".
    QString usesText(const std::vector<std::string>& where) const;

    void refresh();
    void onItemChanged(QTableWidgetItem* item);
    bool apply(const QString& undoText, const std::function<void(Document&)>& edit);

    DocumentSession* session_;
    QTableWidget* table_;
    QPushButton* add_;
    QPushButton* remove_;
    QLabel* error_;
    bool refreshing_ = false;
};

} // namespace kerf::ui
