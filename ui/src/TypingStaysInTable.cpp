#include "TypingStaysInTable.hpp"

#include <QAbstractItemView>
#include <QKeyEvent>

namespace kerf::ui {

void TypingStaysInTable::install(QAbstractItemView* table)
{
    table->installEventFilter(new TypingStaysInTable(table));
}

bool TypingStaysInTable::eventFilter(QObject* watched, QEvent* event)
{
    if (event->type() == QEvent::ShortcutOverride) {
        const auto* key = static_cast<QKeyEvent*>(event);
        const bool plain = !(key->modifiers() & (Qt::ControlModifier | Qt::AltModifier | Qt::MetaModifier));
        if (plain && !key->text().isEmpty() && key->text()[0].isPrint()) {
            event->accept(); // the key press then reaches the table
            return true;
        }
    }
    return QObject::eventFilter(watched, event);
}

} // namespace kerf::ui
