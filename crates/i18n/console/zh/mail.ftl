# 集线器发给临床人员的邮件（crates/hub-care/src/pain_mail.rs），使用收件人的控制台语言。疼痛邮件不含健康数据。

mail-pain-subject = telerehab：{ $pseudonym } 报告了剧烈疼痛
mail-pain-reported = { $pseudonym } 在一次训练后报告的疼痛达到或超过了贵诊所的上限。
mail-pain-told = 训练站已告诉其停止、休息并给诊所打电话。
mail-pain-no-more = 除非您允许，今天不再提供练习。
mail-pain-open = 打开其页面：
mail-pain-page = telerehab 控制台中该患者的页面
mail-pain-signature = telerehab 集线器（本邮件不含健康数据；请见控制台）
