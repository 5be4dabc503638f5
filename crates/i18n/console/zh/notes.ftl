# 治疗师对某次训练的备注（仅供机构存档）。

notes-empty = 备注为空：请写几句话。
notes-too-long = 备注过长：{ $chars } 个字符，最多 { $max } 个。
notes-control = 备注含有控制字符：只能是纯文本。
notes-by = { $by }，{ $when }
notes-by-gone = 已离开本机构的治疗师
notes-none = 尚无备注。
notes-add-label = 为{ $session }添加备注（供机构存档；患者看不到）
notes-save = 保存备注
notes-saved = 备注已保存。
notes-cell = 备注
notes-heading = 本次训练的备注
notes-this-session = 本次训练
