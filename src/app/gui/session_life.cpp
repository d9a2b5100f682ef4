#include "app/gui/session_life.h"

#include <QCoreApplication>
#include <QMessageBox>
#include <QPushButton>

namespace sc::app {

namespace {

QString lifeText(const char* text) { return QCoreApplication::translate("MainWindow", text); }

}  // namespace

SessionQuestion endSessionQuestion(int others) {
  const QString people = others == 1 ? lifeText("1 person is") : lifeText("%1 people are").arg(others);
  return {lifeText("End the session?"),
          lifeText("%1 in this session. End it for everyone?").arg(people),
          lifeText("End session"),
          {}};
}

SessionQuestion openWhileHostingQuestion(const QString& hosted, const QString& opening) {
  return {lifeText("Open another mesh?"), lifeText("You are hosting %1. Open %2:").arg(hosted, opening),
          lifeText("End the session and open"), lifeText("Host %1 instead").arg(opening)};
}

SessionQuestion openWhileJoinedQuestion(const QString& session, const QString& opening) {
  return {lifeText("Open another mesh?"),
          lifeText("You are in the session at %1. Open %2:").arg(session, opening),
          lifeText("Leave the session and open"),
          {}};
}

SessionAnswer askInMessageBox(QWidget* parent, const SessionQuestion& question) {
  QMessageBox box(QMessageBox::Question, question.title, question.text, QMessageBox::NoButton, parent);
  box.setObjectName(QStringLiteral("sessionQuestionBox"));
  box.setTextFormat(Qt::PlainText);  // file names and peer names are never rich text
  QPushButton* end = box.addButton(question.endLabel, QMessageBox::AcceptRole);
  QPushButton* rehost =
      question.rehostLabel.isEmpty() ? nullptr : box.addButton(question.rehostLabel, QMessageBox::ActionRole);
  QPushButton* cancel = box.addButton(QMessageBox::Cancel);
  box.setDefaultButton(cancel);
  box.exec();
  if (box.clickedButton() == end) return SessionAnswer::End;
  if (rehost != nullptr && box.clickedButton() == rehost) return SessionAnswer::Rehost;
  return SessionAnswer::Cancel;
}

}  // namespace sc::app
