#include "CutListDialog.hpp"

#include "LengthDisplay.hpp"

#include "kerf/document/AtomicFile.hpp"

#include <QDialogButtonBox>
#include <QFileDialog>
#include <QFileInfo>
#include <QHeaderView>
#include <QLabel>
#include <QPushButton>
#include <QTableWidget>
#include <QVBoxLayout>
#include <QtConcurrent/QtConcurrentRun>

#include <new>

namespace kerf::ui {

CutListDialog::CutListDialog(const Document& doc, QString partName, QString suggestedFile, QWidget* parent)
    : QDialog(parent), partName_(std::move(partName)), suggestedFile_(std::move(suggestedFile))
{
    setWindowTitle(tr("Cut list — %1").arg(partName_));
    resize(720, 420);
    auto* layout = new QVBoxLayout(this);
    table_ = new QTableWidget(0, 5, this);
    table_->setObjectName("cutlist.table");
    const bool inches = LengthDisplay::instance().unit() == LengthUnit::Inches;
    const QString unit = inches ? tr("in") : tr("mm");
    table_->setHorizontalHeaderLabels({tr("Part"), tr("Qty"), tr("Length (%1)").arg(unit), tr("Width (%1)").arg(unit),
                                       tr("Thickness (%1)").arg(unit)});
    table_->horizontalHeader()->setSectionResizeMode(0, QHeaderView::Stretch);
    table_->setEditTriggers(QAbstractItemView::NoEditTriggers);
    table_->setSortingEnabled(false);
    layout->addWidget(table_);
    status_ = new QLabel(tr("Measuring the bodies…"), this);
    status_->setObjectName("cutlist.status");
    layout->addWidget(status_);
    auto* buttons = new QDialogButtonBox(QDialogButtonBox::Close, this);
    exportButton_ = buttons->addButton(tr("Export CSV…"), QDialogButtonBox::ActionRole);
    exportButton_->setEnabled(false);
    layout->addWidget(buttons);
    connect(buttons, &QDialogButtonBox::rejected, this, &QDialog::reject);
    connect(exportButton_, &QPushButton::clicked, this, [this] {
        QString f = QFileDialog::getSaveFileName(this, tr("Export cut list"), suggestedFile_, tr("CSV files (*.csv)"));
        // A name typed without an extension gets the filter's (Qt's own
        // dialog leaves it as typed: "cutlist2" was written so).
        if (!f.isEmpty() && QFileInfo(f).suffix().isEmpty()) f += ".csv";
        if (!f.isEmpty()) exportCsv(f);
    });
    connect(&watcher_, &QFutureWatcher<std::vector<CutListRow>>::finished, this, [this] {
        try {
            showRows(watcher_.result());
        } catch (const std::bad_alloc&) {
            status_->setText(tr("The cut list could not be made: out of memory."));
        } catch (const std::exception& e) {
            status_->setText(tr("The cut list could not be made: %1").arg(QString::fromUtf8(e.what())));
        }
    });
    watcher_.setFuture(QtConcurrent::run([doc] { return cutList(doc); }));
}

void CutListDialog::showRows(std::vector<CutListRow> rows)
{
    rows_ = std::move(rows);
    table_->setRowCount(int(rows_.size()));
    auto cell = [](const QString& text, bool number) {
        auto* item = new QTableWidgetItem(text);
        if (number) item->setTextAlignment(Qt::AlignRight | Qt::AlignVCenter);
        return item;
    };
    double worst = 0.0;
    for (int r = 0; r < int(rows_.size()); ++r) {
        const CutListRow& row = rows_[std::size_t(r)];
        table_->setItem(r, 0, cell(QString::fromStdString(cutListName(row)), false));
        table_->setItem(r, 1, cell(QString::number(row.quantity), true));
        for (int c = 0; c < 3; ++c) {
            const double v = c == 0 ? row.length : c == 1 ? row.width : row.thickness;
            // Inches to the nearest 64th, "≈" where that rounds: what a tape measure reads.
            const QString shown = LengthDisplay::instance().unit() == LengthUnit::Inches ? LengthDisplay::instance().readout(v)
                                                                                       : QString::number(v, 'f', 2);
            table_->setItem(r, 2 + c, cell(row.unbounded ? tr("unbounded") : shown, true));
        }
        worst = std::max(worst, row.uncertainty);
    }
    // Pieces, with each row's quantity: a mirrored pair is one row and two
    // pieces (a newcomer read "1 body" beside a quantity of 2).
    long pieces = 0;
    for (const CutListRow& row : rows_) pieces += row.quantity;
    const QString counted = rows_.size() == 1 ? tr("1 row") : tr("%1 rows").arg(rows_.size());
    const QString made = pieces == 1 ? tr("1 piece") : tr("%1 pieces").arg(pieces);
    status_->setText(rows_.empty() ? tr("The part has no visible body.")
                                   : tr("%1, %2; dimensions within %3 mm.")
                                         .arg(counted, made)
                                         .arg(std::max(worst, 0.01), 0, 'f', 2));
    exportButton_->setEnabled(!rows_.empty());
    ready_ = true;
    emit computed();
}

bool CutListDialog::exportCsv(const QString& file)
{
    try {
        writeFileAtomically(file.toStdString(), cutListCsv(rows_, LengthDisplay::instance().unit()));
        status_->setText(tr("Wrote %1").arg(file));
        return true;
    } catch (const std::exception& e) {
        status_->setText(tr("Could not write the cut list: %1").arg(QString::fromUtf8(e.what())));
        return false;
    }
}

} // namespace kerf::ui
