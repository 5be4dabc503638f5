# 测量表格的用词（crates/hub-care/src/sheet_words.rs）：第一行表头和给人看的文字；第二行表头保留技术名称。

sheet-col-patient = 患者
sheet-col-session = 训练编号
sheet-col-started-local = 开始时间（当地时间，{ $zone }）
sheet-col-started-utc = 开始时间（UTC）
sheet-col-exercises = 练习
sheet-col-ended = 结束方式
sheet-col-as-prescribed = 是否按处方完成
sheet-col-pain = 训练后疼痛（0–10）
sheet-col-effort = 训练后用力程度（Borg CR10 0–10）
sheet-col-felt = 感觉难度
sheet-yes = 是
sheet-no = 否

# 标准评估表格：每个评估部分的每项测量一行。
sheet-assessment-col-protocol = 协议版本
sheet-assessment-col-seed = 目标跳动的种子
sheet-assessment-col-part-key = 部分（代码）
sheet-assessment-col-part = 部分
sheet-assessment-col-measure-key = 测量项（代码）
sheet-assessment-col-measure = 测量项
sheet-assessment-col-value = 数值
sheet-assessment-col-unit = 单位
