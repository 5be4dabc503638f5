# 机构为化名编号对应的姓名，仅保存在本浏览器中。

names-display = { $name }（{ $pseudonym }）
names-problem-cells = 第 { $line } 行：需先填化名编号，再填姓名。
names-problem-long = 第 { $line } 行：姓名超过 { $max } 个字符。
names-problem-twice = 第 { $line } 行：{ $pseudonym } 在列表中出现两次；保留第一个姓名。
names-problem-many = 第 { $line } 行：超过 { $max } 个姓名；其余未导入。
names-in-caseload = 在您的患者列表中
names-not-in-caseload = 不在您的患者列表中
names-heading = 您的患者姓名
names-stay-heading = 姓名只保存在这台电脑上
names-stay-text = 中心服务器只通过化名编号识别您的患者。您可以把机构自己的姓名列表导入本浏览器。该列表只保存在这台电脑的本浏览器中，绝不会发送到中心服务器。
names-csv-text = 请使用两列的表格文件（CSV）：先是化名编号，再是姓名。导入文件会替换原有列表。
names-file-label = 导入姓名列表（CSV 文件）
names-shared-computer = 如果这台电脑也有其他人使用，请在用完后清除姓名。
names-forget = 清除这台电脑上的姓名
names-list-heading = 本浏览器中的姓名
names-caption = 共 { $count } 个姓名，按化名编号排列
names-col-pseudonym = 化名编号
names-col-name = 姓名
names-col-patient = 患者
names-none = 本浏览器中尚无姓名。
names-none-read = 文件中没有读到任何姓名；列表未更改。
names-kept = 已在本浏览器中保存 { $count } 个姓名。
names-forgotten = 已清除这台电脑上的姓名。
