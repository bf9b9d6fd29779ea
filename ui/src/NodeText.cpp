#include "NodeText.hpp"

#include "kerf/document/NodeTypes.hpp"

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

QString fieldLabel(const Node& n, const std::string& field)
{
    // "key" or "key[i]"; the reader names a placement "transform.translate[2]".
    std::string key = field;
    constexpr std::string_view kTransform = "transform.";
    if (key.starts_with(kTransform)) key.erase(0, kTransform.size());
    int index = -1;
    if (const auto open = key.find('['); open != std::string::npos && key.back() == ']') {
        try {
            index = std::stoi(key.substr(open + 1, key.size() - open - 2));
        } catch (const std::exception&) {
            return QString::fromStdString(field);
        }
        key.resize(open);
    }
    QString label;
    bool hasAxes = false;
    if (key == "translate" || key == "rotate") {
        label = QCoreApplication::translate("kerf::ui::PropertyEditor", key == "translate" ? "Position" : "Rotation");
        hasAxes = true;
    } else {
        for (const FieldSpec& f : nodeTypeSpec(n.type).fields)
            if (f.key == key) {
                label = QCoreApplication::translate("NodeTypes", std::string(f.label).c_str());
                hasAxes = f.shape == FieldShape::Vector || f.shape == FieldShape::Direction || f.shape == FieldShape::Counts;
                if (f.shape == FieldShape::Points && index >= 0)
                    label = QCoreApplication::translate("kerf", "%1, point %2").arg(label).arg(index + 1);
                break;
            }
    }
    if (label.isEmpty()) return QString::fromStdString(field);
    if (hasAxes && index >= 0 && index < 3) label += QStringLiteral(" ") + QChar("XYZ"[index]);
    return label;
}

QString describeRefusal(const Node& root, const std::string& nodeId, const std::string& field,
                        const std::string& reason)
{
    const Node* n = nodeId.empty() ? nullptr : root.find(nodeId);
    const QString why = QString::fromStdString(reason);
    if (!n) {
        if (nodeId.empty()) return field.empty() ? why : QString::fromStdString(field) + ": " + why;
        QString s = QString::fromStdString("'" + nodeId + "'");
        if (!field.empty()) s += QString::fromStdString(", " + field);
        return s + ": " + why;
    }
    const QString label = field.empty() ? QString() : fieldLabel(*n, field);
    // A key no row shows (its children): the feature alone is named.
    if (label.isEmpty() || label == QString::fromStdString(field)) return featureName(*n) + ": " + why;
    return QCoreApplication::translate("kerf", "%1 of %2: %3").arg(label, featureName(*n), why);
}

QString describeExpressionUse(const Node& root, const std::string& use)
{
    constexpr std::string_view kParameters = "parameters.";
    if (use.starts_with(kParameters))
        return QCoreApplication::translate("kerf", "the parameter %1").arg(QString::fromStdString(use.substr(kParameters.size())));
    // An id holds no dot (ids are names), so the first dot ends it.
    const auto dot = use.find('.');
    const Node* n = dot == std::string::npos ? nullptr : root.find(use.substr(0, dot));
    if (!n) return QString::fromStdString(use);
    return QCoreApplication::translate("kerf", "%1 of %2").arg(fieldLabel(*n, use.substr(dot + 1)), featureName(*n));
}

QString describeExpressionUses(const Node& root, const std::vector<std::string>& uses)
{
    constexpr std::size_t kListed = 5;
    QStringList list;
    for (std::size_t i = 0; i < uses.size() && i < kListed; ++i)
        list << describeExpressionUse(root, uses[i]);
    QString text = list.join(", ");
    if (uses.size() > kListed)
        text += QCoreApplication::translate("kerf", " and %n more", nullptr, int(uses.size() - kListed));
    return text;
}

} // namespace kerf::ui
