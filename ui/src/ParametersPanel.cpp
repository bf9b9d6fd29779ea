#include "ParametersPanel.hpp"

#include "DocumentSession.hpp"
#include "LengthDisplay.hpp"
#include "NameCompleter.hpp"
#include "NodeText.hpp"
#include "TypingStaysInTable.hpp"
#include "kerf/document/DocumentEdits.hpp"
#include "kerf/document/NodeTypes.hpp"

#include <QFocusEvent>
#include <QHBoxLayout>
#include <QHeaderView>
#include <QKeyEvent>
#include <QLabel>
#include <QLineEdit>
#include <QPushButton>
#include <QStyledItemDelegate>
#include <QSignalBlocker>
#include <QTableWidget>
#include <QTimer>
#include <QVBoxLayout>

namespace kerf::ui {

namespace {
// The expression column's editor completes parameter names as they are typed.
class ExpressionDelegate : public QStyledItemDelegate {
public:
    ExpressionDelegate(DocumentSession* session, QObject* parent) : QStyledItemDelegate(parent), session_(session) {}
    QWidget* createEditor(QWidget* parent, const QStyleOptionViewItem& option, const QModelIndex& index) const override
    {
        QWidget* editor = QStyledItemDelegate::createEditor(parent, option, index);
        if (auto* line = qobject_cast<QLineEdit*>(editor))
            new NameCompleter(line, [s = session_] { return parameterNames(s->document()); }, false);
        return editor;
    }

protected:
    // The names' popup takes the focus for a moment: that is not leaving the
    // cell (the delegate would commit the half-typed expression).
    bool eventFilter(QObject* editor, QEvent* event) override
    {
        if (event->type() == QEvent::FocusOut && static_cast<QFocusEvent*>(event)->reason() == Qt::PopupFocusReason)
            return false;
        return QStyledItemDelegate::eventFilter(editor, event);
    }

private:
    DocumentSession* session_;
};
} // namespace

ParametersPanel::ParametersPanel(DocumentSession* session, QWidget* parent) : QWidget(parent), session_(session)
{
    auto* layout = new QVBoxLayout(this);
    table_ = new QTableWidget(0, 4, this);
    table_->installEventFilter(this);
    TypingStaysInTable::install(table_);
    table_->setObjectName("parameters.table");
    table_->setHorizontalHeaderLabels({tr("Name"), tr("Expression"), tr("Value"), tr("Comment")});
    table_->verticalHeader()->hide();
    table_->verticalHeader()->setDefaultSectionSize(fontMetrics().height() + 8);
    // Name and value as wide as they need; a long expression is cut (its
    // whole text in the tooltip and the editor), the comment takes the rest.
    table_->horizontalHeader()->setSectionResizeMode(NameColumn, QHeaderView::ResizeToContents);
    table_->horizontalHeader()->setSectionResizeMode(ExpressionColumn, QHeaderView::Interactive);
    table_->horizontalHeader()->setSectionResizeMode(ValueColumn, QHeaderView::ResizeToContents);
    table_->horizontalHeader()->setSectionResizeMode(CommentColumn, QHeaderView::Stretch);
    table_->setColumnWidth(ExpressionColumn, 12 * fontMetrics().averageCharWidth() + 12);
    table_->setWordWrap(false);
    table_->setTextElideMode(Qt::ElideRight);
    table_->setSelectionBehavior(QAbstractItemView::SelectRows);
    table_->setSelectionMode(QAbstractItemView::SingleSelection);
    table_->setEditTriggers(QAbstractItemView::DoubleClicked | QAbstractItemView::EditKeyPressed |
                            QAbstractItemView::AnyKeyPressed);
    table_->setItemDelegateForColumn(ExpressionColumn, new ExpressionDelegate(session_, table_));
    // An edit given up with Esc takes the last refusal's message with it.
    for (QAbstractItemDelegate* d : {table_->itemDelegate(), table_->itemDelegateForColumn(ExpressionColumn)})
        connect(d, &QAbstractItemDelegate::closeEditor, this, [this](QWidget*, QAbstractItemDelegate::EndEditHint hint) {
            if (hint == QAbstractItemDelegate::RevertModelCache) error_->hide();
        });
    layout->addWidget(table_, 1);
    auto* buttons = new QHBoxLayout;
    add_ = new QPushButton(tr("Add"), this);
    add_->setObjectName("parameters.add");
    add_->setToolTip(tr("A new parameter: give it a name and an expression (18mm, 3/4in, height - 2 * thickness)"));
    remove_ = new QPushButton(tr("Delete"), this);
    remove_->setObjectName("parameters.delete");
    remove_->setToolTip(tr("Delete the selected parameter (not while an expression uses it)"));
    buttons->addWidget(add_);
    buttons->addWidget(remove_);
    buttons->addStretch(1);
    // Between the table and the buttons: the buttons stay where they are
    // when a refusal shows (below them it moved them up, and a newcomer's
    // next click missed Add).
    error_ = new QLabel(this);
    error_->setObjectName("parameters.error");
    error_->setWordWrap(true);
    error_->setStyleSheet("color: #b00020;");
    error_->hide();
    layout->addWidget(error_);
    layout->addLayout(buttons);

    connect(add_, &QPushButton::clicked, this, &ParametersPanel::addParameter);
    connect(remove_, &QPushButton::clicked, this, &ParametersPanel::removeSelected);
    connect(table_, &QTableWidget::itemChanged, this, &ParametersPanel::onItemChanged);
    connect(session_, &DocumentSession::documentChanged, this, &ParametersPanel::refresh);
    // A refusal is about the document as it was: any change (an undo, an
    // edit in the Properties) makes it stale. (A refused edit changes nothing.)
    connect(session_, &DocumentSession::documentChanged, error_, &QWidget::hide);
    connect(&LengthDisplay::instance(), &LengthDisplay::changed, this, &ParametersPanel::refresh);
    refresh();
}

QString ParametersPanel::error() const { return error_->isVisible() ? error_->text() : QString(); }

void ParametersPanel::refresh()
{
    const QSignalBlocker block(table_);
    refreshing_ = true;
    const std::vector<Parameter>& params = session_->document().parameters;
    table_->setRowCount(int(params.size()));
    for (int r = 0; r < int(params.size()); ++r) {
        const Parameter& p = params[std::size_t(r)];
        const QString unit = p.unit == "length" ? tr(" mm") : p.unit == "angle" ? tr("°") : QString();
        auto set = [&](int column, const QString& text, bool editable) {
            QTableWidgetItem* item = table_->item(r, column);
            if (!item) {
                item = new QTableWidgetItem;
                table_->setItem(r, column, item);
            }
            item->setText(text);
            item->setFlags(editable ? item->flags() | Qt::ItemIsEditable : item->flags() & ~Qt::ItemIsEditable);
        };
        set(NameColumn, QString::fromStdString(p.name), true);
        set(ExpressionColumn, QString::fromStdString(p.expression), true);
        const bool inches = p.unit == "length" && LengthDisplay::instance().unit() == LengthUnit::Inches;
        set(ValueColumn, inches ? LengthDisplay::instance().readout(p.value) : QString::fromStdString(formatFieldNumber(p.value)) + unit,
            false);
        set(CommentColumn, QString::fromStdString(p.comment.value_or("")), true);
        table_->item(r, ExpressionColumn)->setToolTip(QString::fromStdString(p.expression));
        table_->item(r, CommentColumn)->setToolTip(QString::fromStdString(p.comment.value_or("")));
        const QString uses = [&] {
            const std::vector<std::string> where = edit::parameterUses(session_->document(), p.name);
            if (where.empty()) return tr("Not used yet");
            return tr("Used by %1").arg(usesText(where));
        }();
        table_->item(r, NameColumn)->setToolTip(uses);
        table_->item(r, ValueColumn)->setToolTip(uses);
    }
    refreshing_ = false;
}

bool ParametersPanel::apply(const QString& undoText, const std::function<void(Document&)>& edit)
{
    QString why;
    const bool ok = session_->apply(undoText, edit, &why);
    if (ok) {
        error_->hide();
    } else {
        error_->setText(why);
        error_->show();
        refresh(); // the table shows the document as it stays; the message says why
    }
    return ok;
}

void ParametersPanel::onItemChanged(QTableWidgetItem* item)
{
    if (refreshing_) return;
    const int r = item->row();
    const std::vector<Parameter>& params = session_->document().parameters;
    if (r < 0 || r >= int(params.size())) return;
    const std::string name = params[std::size_t(r)].name;
    const std::string text = item->text().trimmed().toStdString();
    // Typed in the cell's editor (not set by the program): a refusal opens
    // the editor again on what was typed, to mend (a newcomer lost a long
    // formula to one misspelt name), while the cell shows the document.
    const bool typed = table_->indexWidget(table_->model()->index(r, item->column())) != nullptr; // its editor is open
    const QString typedText = item->text();
    const int column = item->column();
    const auto reopenIfRefused = [&](bool applied) {
        if (applied || !typed) return;
        QTimer::singleShot(0, this, [this, r, column, typedText] {
            if (error_->isHidden() || r >= table_->rowCount()) return; // given up or overtaken meanwhile
            table_->setCurrentCell(r, column);
            const QModelIndex index = table_->model()->index(r, column);
            table_->edit(index);
            if (auto* editor = qobject_cast<QLineEdit*>(table_->indexWidget(index))) editor->setText(typedText);
        });
    };
    switch (item->column()) {
    case NameColumn:
        reopenIfRefused(apply(tr("Rename parameter %1").arg(QString::fromStdString(name)),
                              [&](Document& d) { edit::renameParameter(d, name, text); }));
        break;
    case ExpressionColumn:
        reopenIfRefused(apply(tr("Set %1").arg(QString::fromStdString(name)), [&](Document& d) {
            for (Parameter& p : d.parameters)
                if (p.name == name) p.expression = text;
        }));
        break;
    case CommentColumn:
        apply(tr("Comment on %1").arg(QString::fromStdString(name)), [&](Document& d) {
            for (Parameter& p : d.parameters)
                if (p.name == name) p.comment = text.empty() ? std::nullopt : std::optional(text);
        });
        break;
    default: break;
    }
}

void ParametersPanel::addParameter()
{
    std::string added;
    if (!apply(tr("Add parameter"), [&](Document& d) { added = edit::addParameter(d, "p", "0"); })) return;
    for (int r = 0; r < table_->rowCount(); ++r)
        if (table_->item(r, NameColumn)->text() == QString::fromStdString(added)) {
            table_->setCurrentCell(r, NameColumn);
            table_->editItem(table_->item(r, NameColumn));
        }
}

bool ParametersPanel::eventFilter(QObject* watched, QEvent* event)
{
    if (watched == table_ && (event->type() == QEvent::ShortcutOverride || event->type() == QEvent::KeyPress)) {
        const auto* key = static_cast<QKeyEvent*>(event);
        if (key->matches(QKeySequence::Delete) || key->key() == Qt::Key_Backspace) {
            if (event->type() == QEvent::ShortcutOverride) {
                event->accept(); // the key is the table's, not the window's Delete
                return true;
            }
            removeSelected();
            return true;
        }
        // Esc takes back a refusal's message with the edit it was about:
        // the table already shows the document as it stays, and a newcomer
        // saw "mm is a unit…" stay under it after Esc. Claimed only while
        // a message shows (else Esc is the window's: clearing a measurement).
        if (key->key() == Qt::Key_Escape && error_->isVisible()) {
            if (event->type() == QEvent::KeyPress) error_->hide();
            event->accept();
            return true;
        }
    }
    return QWidget::eventFilter(watched, event);
}

void ParametersPanel::removeSelected()
{
    const int r = table_->currentRow();
    const std::vector<Parameter>& params = session_->document().parameters;
    if (r < 0 || r >= int(params.size())) return;
    const std::string name = params[std::size_t(r)].name;
    // Refused here in the panel's words (the document's own refusal names
    // ids and keys: "used by board.size[0]").
    const std::vector<std::string> where = edit::parameterUses(session_->document(), name);
    if (!where.empty()) {
        error_->setText(tr("%1 is used by %2: change those first.").arg(QString::fromStdString(name), usesText(where)));
        error_->show();
        return;
    }
    apply(tr("Delete parameter %1").arg(QString::fromStdString(name)), [&](Document& d) { edit::removeParameter(d, name); });
}

QString ParametersPanel::usesText(const std::vector<std::string>& where) const
{
    return describeExpressionUses(session_->document().root, where);
}

} // namespace kerf::ui
