#include "NodeText.hpp"

#include <QCoreApplication>

namespace kerf::ui {

QString nodeTypeLabel(NodeType type)
{
    QString s = QString::fromUtf8(nodeTypeName(type).data(), qsizetype(nodeTypeName(type).size()));
    if (!s.isEmpty()) s[0] = s[0].toUpper();
    return QCoreApplication::translate("kerf", s.toUtf8().constData());
}

QString displayName(const Node& n) { return QString::fromStdString(n.name.value_or(n.id)); }

QString featureName(const Node& n)
{
    return n.name ? QString::fromStdString(*n.name) : QCoreApplication::translate("kerf", "the %1").arg(nodeTypeLabel(n.type).toLower());
}

} // namespace kerf::ui
