#include "app/gui/session_life.h"

#include <QCoreApplication>
#include <QMessageBox>
#include <QPushButton>

namespace sc::app {

namespace {

QString tr(const char* text, int n = -1) { return QCoreApplication::translate("MainWindow", text, nullptr, n); }

}  // namespace

SessionQuestion endSessionQuestion(int others) {
  const QString people = others == 1 ? tr("1 person is") : tr("%1 people are").arg(others);
  return {tr("End the session?"), tr("%1 in this session. End it for everyone?").arg(people), tr("End session"), {}};
}

SessionQuestion openWhileHostingQuestion(const QString& hosted, const QString& opening) {
  return {tr("Open another mesh?"), tr("You are hosting %1. Open %2:").arg(hosted, opening),
          tr("End the session and open"), tr("Host %1 instead").arg(opening)};
}

SessionQuestion openWhileJoinedQuestion(const QString& session, const QString& opening) {
  return {tr("Open another mesh?"), tr("You are in the session at %1. Open %2:").arg(session, opening),
          tr("Leave the session and open"), {}};
}

SessionAnswer askInMessageBox(QWidget* parent, const SessionQuestion& question) {
  QMessageBox box(QMessageBox::Question, question.title, question.text, QMessageBox::NoButton, parent);
  box.setObjectName(QStringLiteral("sessionQuestionBox"));
  box.setTextFormat(Qt::PlainText);  // file names and peer names are never rich text
  QPushButton* end = box.addButton(question.endLabel, QMessageBox::AcceptRole);
  QPushButton* rehost = question.rehostLabel.isEmpty() ? nullptr : box.addButton(question.rehostLabel,
                                                                                 QMessageBox::ActionRole);
  QPushButton* cancel = box.addButton(QMessageBox::Cancel);
  box.setDefaultButton(cancel);
  box.exec();
  if (box.clickedButton() == end) return SessionAnswer::End;
  if (rehost != nullptr && box.clickedButton() == rehost) return SessionAnswer::Rehost;
  return SessionAnswer::Cancel;
}

}  // namespace sc::app
